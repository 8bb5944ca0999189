"""Tests of the gas-only rules (``fixed.sizing_rules = "gas_only"``: walls sized for the gas peak at nominal size,
no joints, no damper loads): the rules the unit was designed by before the buildability rules, still available
behind that flag. Their numbers (the 1.3265 % optimum, the sized walls' hand calculations, the published
relaxations) are those rules'; a test module of them makes ``FixedParameters()`` default to them with
:func:`gas_only_defaults` (a module fixture), so every design it builds, through ``Requirements()`` or
``Design(...)`` alike, is sized by them. The buildability rules' own tests are ``test_buildability*.py``."""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import fields

from vvea_design.spring.parameters import FixedParameters


@contextmanager
def gas_only_defaults():
    """``FixedParameters()`` defaults to ``sizing_rules = "gas_only"`` inside the block (its other defaults kept)."""
    init = FixedParameters.__init__
    names = [f.name for f in fields(FixedParameters)]
    old = init.__defaults__
    assert len(old) == len(names), "every FixedParameters field has a default"
    i = names.index("sizing_rules")
    init.__defaults__ = old[:i] + ("gas_only",) + old[i + 1:]
    try:
        yield
    finally:
        init.__defaults__ = old


#: The gas-only rules' fixed parameters (the defaults otherwise), for designs built when a module is imported.
GAS_ONLY = FixedParameters(sizing_rules="gas_only")
