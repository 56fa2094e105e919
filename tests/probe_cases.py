"""Case-file text shared by the validation tests: the smallest valid block case (a rigid circle, force control)."""

PROBE_BLOCK = """
[case]
name = "probe"
[material]
E = 210000.0
nu = 0.3
[geometry]
scene = "block"
indenter = "circle"
radius = 10.0
[loading]
control = "force"
P = 100.0
"""
