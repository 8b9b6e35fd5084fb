# Import the Component and Joint Type
from fabkit.flatpack import Component
from fabkit.flatpack import FingerJoint
# Initialize the component
Component = Component()
# Select the predefined components
Component.addSubcomponent("A", "Rectangle")
Component.addSubcomponent("B", "Rectangle")
# Add the dimensional constraints
Component.addParameter("l1", 30, paramtype="length")
Component.addParameter("l2", 60, paramtype="length")
# Specify the dimensional constraint for the components
Component.addConstraint(("A","l"), "l1")
Component.addConstraint(("A","w"), "l2")
Component.addConstraint(("B","l"), "l1")
Component.addConstraint(("B","w"), "l2")
# Define the connection between components
Component.addEdgeToEdge(
    ("A", "t"),("B","b"), orientation="front-front",
    offset = (0,0,0), angle=(90, 0, 0))
# Save the design file for later hierarchical composition design
Component.toYaml("library/ConnectionJointBuilder.yaml")
# Generate the output files for the design
Component.makeOutput(
    "output/ConnectionJointBuilder", tree=False,
    display=False, thickness=3, joint=FingerJoint(thickness=3))
