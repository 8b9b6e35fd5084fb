from fabkit.hacks import *  # the only line added to the paper's program

assembly = Assembly()

# adding the starting environment
ENV_start = Environment({"part": TowelRackRods()})
assembly.add(ENV_start, Frame([0,0,200], [0,0,-90]))

# connecting the eyehooks to the starting environment
eyehook1 = HookEyeConnector()
eyehook2 = HookEyeConnector()
assembly.connect(eyehook1.hole, ENV_start.rod1, alignment="flip")
assembly.connect(eyehook2.hole, ENV_start.rod2)

# adding the target part and connecting the eyehooks to it
ENV_end = Environment({"part": RoundHandleBasket()})
assembly.connect(eyehook1.hook, ENV_end.hook)
assembly.connect(eyehook2.hook, ENV_end.hook)
assembly.end_with(ENV_end, Frame([0,0,100], [-75,0,90]))
