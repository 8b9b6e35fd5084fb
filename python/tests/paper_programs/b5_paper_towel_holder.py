from fabkit.hacks import *  # the only line added to the paper's program

ASSEMBLY_paper_towel_holder = Assembly()

ENV_start = Environment({"env": TowelHangingEnv()})
ENV_end = Environment({"paper_towel_roll": PaperTowelRoll()})

wall_frame = Frame([0,0,300], [0,0,0])
ASSEMBLY_paper_towel_holder.add(ENV_start, wall_frame)

PART_hokeye1 = HookEyeLeft()
PART_hokeye2 = HookEyeLeft()
PART_broomrod = BroomRod()
ASSEMBLY_paper_towel_holder.connect(PART_hokeye1.hole, ENV_start.hook1)
ASSEMBLY_paper_towel_holder.connect(PART_hokeye2.hole, ENV_start.hook2)
ASSEMBLY_paper_towel_holder.connect(PART_broomrod.tube, PART_hokeye1.hook, is_fixed=True)
ASSEMBLY_paper_towel_holder.connect(ENV_end.tube, PART_broomrod.tube)
ASSEMBLY_paper_towel_holder.connect(PART_hokeye2.hook, PART_broomrod.tube, is_fixed=True)

end_frame = Frame([53,0,160], [-90,-60,0])
ASSEMBLY_paper_towel_holder.end_with(ENV_end.tube, end_frame)
