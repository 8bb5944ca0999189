"""Designs the CAD tests draw (shared by tests/test_cad*.py; holds no tests itself)."""

from vvea_design.design import Design, FixedParameters

#: The reference design (section-3 scale) and other feasible ones: drawable,
#: walls above the hoop-stress minimum, bladder room at both stroke ends.
REFERENCE = Design(35.18, 59.5, 47107.0, 99735.0)
OTHERS = {
    "d30_D55": Design(30.0, 55.0, 40000.0, 70000.0),
    "d33_D57": Design(33.0, 57.0, 45000.0, 85000.0),
}
#: Extra designs for the slow run (other fixed parameters too).
SLOW = {
    "d36_D62": Design(36.0, 62.0, 50000.0, 110000.0),
    "travel30_dead": Design(32.0, 57.0, 42000.0, 80000.0,
                            fixed=FixedParameters(travel_mm=30.0, dead_volume_1_mm3=2000.0, dead_volume_2_mm3=3000.0)),
}
DESIGNS = {"reference": REFERENCE, **OTHERS}
