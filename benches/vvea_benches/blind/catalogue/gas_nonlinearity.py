"""``gas_nonlinearity``: the antagonistic isothermal chambers of paper eq. 5.

Physics
-------
This form is the base unit itself with ``gas_law="chambers"``: chamber 2 (30 mm piston, V2 of the
oil fill) is compressed and stiffens, chamber 1 (57.1 mm bore, V1 = 1.22e5 mm³) expands and
softens, ``F = A2 p2 V2/(V2 - A2 x) - A1 p1 V1/(V1 + A1 x)`` with ``p1`` from eq. 7. Every
campaign built on that base (all but the strict null campaigns) holds it. The mechanism edits
nothing; the campaign generator switches the base's gas law.
"""

from __future__ import annotations

from ..spec import MechanismSpec


def apply(params, ctx, mods) -> None:
    """Nothing to edit: the chambers are the base's gas law.

    Parameters
    ----------
    params : dict
        Unused.
    ctx : CampaignContext
        The campaign; its base must use ``gas_law="chambers"``.
    mods : list of ExperimentMods
        Unchanged.

    Raises
    ------
    ValueError
        If the campaign's base uses the linear gas law.
    """
    if ctx.base.gas_law != "chambers":
        raise ValueError("gas_nonlinearity needs a base with gas_law='chambers'")


SPEC = MechanismSpec(
    name="gas_nonlinearity",
    domain="gas",
    description="the spring follows the antagonistic isothermal chamber law (eq. 5), not a line",
    states=("position", "charge"),
    ranges={},
    apply=apply,
    catalogue_id="gas_nonlinearity",
)
