from fabkit.hacks import *  # the only line added to the paper's program

ASSEMBLY_cable_holder = Assembly()

edge = Edge({"width": 100, "length": 200, "height": 1.5})
ENV_start = Environment({"edge": edge})
ENV_end = Environment({"cable": Cable()})

start_frame = Frame([0, 0, 150], [0, 0, 0])
ASSEMBLY_cable_holder.add(ENV_start.edge, start_frame)

PART_binderclip = BinderClip()
ASSEMBLY_cable_holder.connect(PART_binderclip.clip, ENV_start.edge, is_fixed=True)
ASSEMBLY_cable_holder.connect(ENV_end.rod1, PART_binderclip.hole1)
ASSEMBLY_cable_holder.connect(ENV_end.rod1, PART_binderclip.hole2)

end_frame = Frame([0, 57.5, 163], [0, 0, 0])
ASSEMBLY_cable_holder.end_with(ENV_end.rod2, end_frame)
