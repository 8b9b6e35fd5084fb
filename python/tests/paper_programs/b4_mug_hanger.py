from fabkit.hacks import *  # the only line added to the paper's program

ASSEMBLY_mug_hanger = Assembly()

rod = Rod({"length": 500, "radius": 2})
ENV_start = Environment({"rod": rod})
surface = Surface({"length": 800, "width": 600})
ENV_wall = Environment({"wall": surface})
ENV_end = Environment({"mug": Mug()})

start_frame = Frame([0,0,200], [90,0,90])
ASSEMBLY_mug_hanger.add(ENV_start.rod, start_frame)
wall_frame = Frame([0,50,0], [90,0,0])
ASSEMBLY_mug_hanger.add(ENV_wall.wall, wall_frame)

PART_doublehook1 = DoubleHook()
PART_doublehook2 = DoubleHook()
PART_doublehook3 = DoubleHook()
ASSEMBLY_mug_hanger.connect(PART_doublehook1.hook2, ENV_start.rod)
ASSEMBLY_mug_hanger.connect(PART_doublehook2.hook2, PART_doublehook1.hook1)
ASSEMBLY_mug_hanger.connect(PART_doublehook3.hook1, PART_doublehook2.hook1)
ASSEMBLY_mug_hanger.connect(ENV_end.hook, PART_doublehook3.hook2)

end_frame = Frame([0,0,50], [-35,0,-90])
ASSEMBLY_mug_hanger.end_with(ENV_end.hook, end_frame)
