from fabkit.hacks import *  # the only line added to the paper's program

ASSEMBLY_diaper_caddy = Assembly()

ENV_start = Environment({"backseat": BackSeats()})
ENV_end = Environment({"diaper_caddy": DiaperCaddy()})

start_frame = Frame([0,0,0], [0,0,0])
ASSEMBLY_diaper_caddy.add(ENV_start, start_frame)

PART_doublehook1 = DoubleHook()
PART_doublehook2 = DoubleHook()
PART_doublehook3 = DoubleHook()
PART_doublehook4 = DoubleHook()
ASSEMBLY_diaper_caddy.connect(PART_doublehook1.hook1, ENV_start.rod1)
ASSEMBLY_diaper_caddy.connect(PART_doublehook2.hook2, ENV_start.rod2)
ASSEMBLY_diaper_caddy.connect(PART_doublehook3.hook1, PART_doublehook1.hook2)
ASSEMBLY_diaper_caddy.connect(PART_doublehook4.hook1, PART_doublehook2.hook1)
ASSEMBLY_diaper_caddy.connect(ENV_end.hook2, PART_doublehook3.hook2)
ASSEMBLY_diaper_caddy.connect(ENV_end.hook1, PART_doublehook4.hook2)

end_frame = Frame([124.3,580,717.1], [-135.5,-40,20.5])
ASSEMBLY_diaper_caddy.end_with(ENV_end.hook2, end_frame)
