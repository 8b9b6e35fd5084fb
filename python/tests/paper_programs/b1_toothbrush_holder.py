from fabkit.hacks import *  # the only line added to the paper's program

ASSEMBLY_toothbrush_holder = Assembly()
surface = Surface({"width": 400, "length": 400})
ENV_start = Environment({"surface": surface})
ENV_end = Environment({"toothbrush": Toothbrush()})

start_frame = Frame()
ASSEMBLY_toothbrush_holder.add(ENV_start, start_frame)

PART_clip = PlasticClip()
ASSEMBLY_toothbrush_holder.connect(PART_clip.hemisphere1, ENV_start.surface)
ASSEMBLY_toothbrush_holder.connect(PART_clip.hemisphere2, ENV_start.surface)
ASSEMBLY_toothbrush_holder.connect(ENV_end.rod, PART_clip.clip)
ASSEMBLY_toothbrush_holder.connect(ENV_end.hemisphere, ENV_start.surface)

end_frame = Frame([-10, -62.5, 50], [-65, 0, 0])
ASSEMBLY_toothbrush_holder.end_with(ENV_end, end_frame)
