"""Designs the CAD tests draw (shared by tests/cad/ and tests/report/; holds no tests itself)."""

import warnings

from tests.helpers import REPO
from vvea_design.spring.design import Design, FixedParameters
from vvea_design.spring.design_file import load_design

#: The designs below were optimised under the gas-only rules (walls for the gas peak, no joints): they keep them
#: (``fixed.sizing_rules = "gas_only"``), as the reference design file does when it loads.
GAS_ONLY = FixedParameters(sizing_rules="gas_only")

#: The reference optimised design (cad/design.json, `vvea optimise` on the default requirements) and
#: other designs the optimiser returned (Pareto points of studies/optimise_design.py): each feasible
#: under its requirements - walls above the hoop-stress minimum, bladder room at both stroke ends.
with warnings.catch_warnings():  # a design file from before the buildability rules loads as gas_only, with a warning
    warnings.simplefilter("ignore", UserWarning)
    REFERENCE = load_design(REPO / "cad" / "design.json")
#: The bulkhead optimum of the gas-only rules (the reference design file before the buildability rules, kept in
#: studies/results/optimise/design.json): the tests about the bulkhead layout's pieces, spaces and cross ports draw it.
BULKHEAD = Design(35.41803947015589, 59.49999999999998, 48819.594401338036, 102178.39086203951, layout="bulkhead",
                  V2_top_mm3=4735.253321212185, fixed=GAS_ONLY)
OTHERS = {
    # the optimum with the bladder's cast fill as a decision variable (`optimise_cast_fill = true`, FE strain
    # bound at the 25 % allowable; studies/bench_optimise.py): the bladder cast near x = 0
    "cast_fill_free": Design(35.727730407763104, 59.5, 51179.87267095346, 105506.77087310137, layout="bulkhead",
                             V2_top_mm3=3337.177199356739,
                             fixed=FixedParameters(bladder_cast_fill=0.1533713521309544, sizing_rules="gas_only")),
    # the annulus_top optimum of the unseen short-housing requirements (65 x 120 mm, 50 mm travel, 80 N/mm;
    # studies/bench_optimise.py): chamber-1 gas also in the annulus above the collar
    "annulus_top_short": Design(34.373592304325015, 65.0, 45706.09615792426, 108669.22305813522, layout="annulus_top",
                                V1_annulus_mm3=12516.61122629605,
                                fixed=FixedParameters(travel_mm=50.0, sizing_rules="gas_only")),
}
#: A cupped piston (`fixed.piston_pocket`): the optimum of examples/paper_tight.toml (`vvea optimise --spec
#: examples/paper_tight.toml`, seed 0: bulkhead, pocket 4,046 mm³, floor 4.37 mm, bladder cast near x = 0).
#: Drawn in the default run by tests/cad/test_cad.py's pocket tests (piston, chamber 1, interference), in full in the
#: slow run (SLOW).
POCKET = Design(36.25872487311745, 59.5, 55396.278750715785, 111402.24160741588, layout="bulkhead",
                V2_top_mm3=9391.457271224454,
                fixed=FixedParameters(piston_pocket=True, fluid_clearance_mm=0.5, min_base_mm=11.0,
                                      bladder_cast_fill=0.14958958987549847, sizing_rules="gas_only"))
#: Extra designs for the slow run (other sizes and fixed parameters). The default run draws the reference
#: (bulkhead), the bladder cast near x = 0 and annulus_top here, and an inner_tube design in
#: tests/pipeline/test_pipeline.py (the main job's CAD, checked from its manifest).
SLOW = {
    # best design for a 50 N/mm minimum stiffness (pareto_stiffness.csv; inner_tube)
    "pareto_k50": Design(31.80382882729851, 56.138773074235885, 46473.411225847376, 88023.80120096414, fixed=GAS_ONLY),
    # best design for a 55 mm envelope (pareto_outer_diameter.csv)
    "pareto_D55": Design(31.084483065248904, 54.99983172964962, 22677.213667025644, 63344.967651658226,
                         fixed=GAS_ONLY),
    "d36_D62": Design(36.0, 62.0, 50000.0, 110000.0, fixed=GAS_ONLY),
    "travel30_dead": Design(32.0, 57.0, 42000.0, 80000.0,
                            fixed=FixedParameters(travel_mm=30.0, dead_volume_1_mm3=2000.0, dead_volume_2_mm3=3000.0,
                                                  sizing_rules="gas_only")),
    "pocket_tight": POCKET,
}
DESIGNS = {"reference": REFERENCE, **OTHERS}
#: Designs sized by the buildability rules, one per joint (issue 23): the CAD draws their joints (threads and run-outs,
#: the ring's counterbore and groove, the tie rods' holes); points near the default optimum's sizes.
JOINTS = {
    "thread_inner_tube": Design(33.0, 59.3, 33000.0, 75000.0, joint="thread"),
    "ring_top_inner_tube": Design(33.0, 59.3, 33000.0, 65000.0, joint="ring_top"),
    # a 70 mm envelope: no 1.78 mm ring fits its tube's bore in the stretch window, so the joints' seals are sized
    # for the 2.62 mm series (the seal zones reserve that ring's gland and lead-in)
    "tie_rods_inner_tube": Design(30.0, 70.0, 33000.0, 80000.0, joint="tie_rods",
                                  fixed=FixedParameters(joint_seal_cross_section_mm=2.62)),
    "thread_annulus_top": Design(33.0, 59.3, 33000.0, 55000.0, layout="annulus_top", V1_annulus_mm3=4000.0),
}
