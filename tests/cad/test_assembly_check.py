"""The assembly check on the units the optimiser makes (issue 23, items 1, 2 and 9): the parts go together in
order and no O-ring passes a thread's crests or a sharp edge (ISO 3601-2), for every joint and every layout.

The seal zone lies inside the thread's minor diameter by the ring's passage (the free ring and the bore's 15-20 deg
lead-in below ``D1``, ISO 965-1), behind the tube's internal thread run-out (DIN 76-1); the ``ring_top`` cap plug
seals in the bore below its counterbore. One design per joint runs by default, the other layouts in the slow run.
"""

from __future__ import annotations

import pytest

from tests.cad.cases import JOINTS
from vvea_design.cad import build_cad
from vvea_design.cad.layout import Layout
from vvea_design.cad.sequence import AssemblyStep, _crossing, check_assembly, thread_crests
from vvea_design.spring.design import Design
from vvea_design.spring.joints import joint_fits_layout, seal_passage_mm

#: The default optimum of the buildability rules (`vvea design` on the built-in defaults, seed 0): an inner_tube
#: unit with threaded joints (M56x1.5-5H/5g6g), 2.337 % linearity. The main job's own run checks it again
#: (tests/pipeline/test_pipeline.py reads its manifest's ``assembly``).
DEFAULT_OPTIMUM = Design(31.370209714990583, 59.06145152410704, 24025.773278476147, 65482.48316618461,
                         joint="thread")

#: One design per joint and layout the slow run checks (points near the default optimum's sizes; tie rods in a
#: 70 mm envelope).
SLOW_CASES = {
    "thread_inner_tube": JOINTS["thread_inner_tube"],
    "thread_bulkhead": Design(33.0, 59.3, 33000.0, 75000.0, layout="bulkhead", V2_top_mm3=3000.0),
    "thread_annulus_top": JOINTS["thread_annulus_top"],
    "ring_top_annulus_top": Design(33.0, 59.3, 33000.0, 55000.0, joint="ring_top", layout="annulus_top",
                                   V1_annulus_mm3=4000.0),
    "tie_rods_bulkhead": Design(30.0, 70.0, 33000.0, 85000.0, joint="tie_rods", layout="bulkhead",
                                V2_top_mm3=3000.0),
    "tie_rods_annulus_top": Design(28.0, 70.0, 30000.0, 50000.0, joint="tie_rods", layout="annulus_top",
                                   V1_annulus_mm3=4000.0),
}


def _assert_passes(design: Design) -> None:
    model = build_cad(design)
    check = check_assembly(model.solids, model.layout)
    bad = [(s.step.number, s.max_overlap_mm, s.where, [c.to_dict() for c in s.crossings if not c.ok])
           for s in check.steps if not s.passes]
    assert check.passes, bad
    # every O-ring fitted before an insertion is checked against the part it passes
    rings = {c.ring for s in check.steps for c in s.crossings}
    assert {"piston", "rod", "base"} <= rings
    assert ("cap" in rings) == (model.layout.cap_seal is not None)


def test_assembly_passes_on_the_default_optimum():
    _assert_passes(DEFAULT_OPTIMUM)


@pytest.mark.parametrize("name", ["ring_top_inner_tube", "tie_rods_inner_tube"])
def test_assembly_passes_for_each_joint(name):
    _assert_passes(JOINTS[name])


@pytest.mark.slow
@pytest.mark.parametrize("name", list(SLOW_CASES))
def test_assembly_passes_for_each_layout(name):
    _assert_passes(SLOW_CASES[name])


def test_the_seal_bore_lies_inside_the_threads_minor_diameter():
    """The design reserves the ring's passage: the bore at its largest, the free ring and the lead-in inside D1."""
    for d in (DEFAULT_OPTIMUM, JOINTS["thread_annulus_top"]):
        lay = Layout(d)
        passage = seal_passage_mm(d.fixed.joint_seal_cross_section_mm)
        for t in (lay.joint.base_thread, lay.joint.cap_thread):
            assert lay.r_bore + passage <= t.internal_minor_mm / 2 + 1e-9
            assert lay.z_lead_in_bottom >= lay.joint.base_thread.relief[1] - 1e-9
        for g in (lay.base_seal, lay.cap_seal, lay.collar_seal):
            if g is not None:
                assert g.lead_in().depth_mm <= passage + 1e-9  # the CAD's chamfer fits under the crests


def test_a_ring_over_a_thread_is_detected():
    """A ring whose band reaches the internal thread's crests fails, though the thread is drawn at its pitch."""
    lay = Layout(JOINTS["thread_inner_tube"])
    g = lay.base_seal
    (r_crest, z0, z1), _ = thread_crests(lay)["housing_outer_tube"]
    step = AssemblyStep(5, "outer tube down", ("housing_outer_tube",), ("housing_base",), 120.0)
    ok = _crossing(step, "base", g, "housing_outer_tube", (lay.z_base_seal,), False, [], ((r_crest, z0, z1),))
    assert ok.ok and not ok.edges
    low = g.sliding_diameter_mm / 2 + 0.5 * g.protrusion_mm  # a thread whose minor diameter the ring reaches
    bad = _crossing(step, "base", g, "housing_outer_tube", (lay.z_base_seal,), False, [], ((low, z0, z1),))
    assert not bad.ok and any("thread crests" in e for e in bad.edges)


def test_bulkhead_has_no_retaining_ring():
    """The ring's plug leaves no side face for the bulkhead's cross port: the optimiser does not try the pair."""
    assert not joint_fits_layout("ring_top", "bulkhead")
    assert all(joint_fits_layout(j, lay) for j in ("thread", "tie_rods")
               for lay in ("inner_tube", "bulkhead", "annulus_top"))
