from fabkit.hacks import *  # the only line added to the paper's program

ASSEMBLY_soapbottle_holder = Assembly()

rod = Rod({"length": 500, "radius": 5})
ENV_start = Environment({"door": rod})
ENV_end = Environment({"soapbottle": SoapBottle()})

start_frame = Frame([0, 0, 500], [90, 0, 90])
ASSEMBLY_soapbottle_holder.add(ENV_start.door, start_frame)
PART_hokeye1 = HookEyeLeft5()
ASSEMBLY_soapbottle_holder.connect(PART_hokeye1.hole, ENV_start.door)
PART_basket = Basket()
ASSEMBLY_soapbottle_holder.connect(PART_basket.rod1, PART_hokeye1.hook)
PART_hokeye2 = HookEyeLeft5()
ASSEMBLY_soapbottle_holder.connect(PART_hokeye2.hole, ENV_start.door, alignment="flip")
ASSEMBLY_soapbottle_holder.connect(PART_hokeye2.hook, PART_basket.rod2)
ASSEMBLY_soapbottle_holder.connect(ENV_end.surface, PART_basket.surface)

end_frame = Frame([0,0,253], [0,0,180])
ASSEMBLY_soapbottle_holder.end_with(ENV_end, end_frame)
