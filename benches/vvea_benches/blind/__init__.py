"""Blind bench for ``vvea diagnose``: mechanism simulators written from the physics, a campaign
generator, a scorer and peer methods.

The bench treats ``vvea diagnose`` as a black box (a subprocess and its ``report.json``); nothing
here imports the diagnosis. Layout:

- ``unit.py`` — base physics of the unit (eq. 5 chambers, laminar throttle, Coulomb friction);
- ``motion.py`` — crosshead motion and the campaign's run plan;
- ``simulate.py`` — one experiment's force from the base and the mechanisms' edits;
- ``spec.py`` — how a mechanism is described (ranges, states);
- ``mechanisms/`` — mechanisms outside the catalogue, one module each;
- ``catalogue/`` — the bench's own forms of the seven catalogue effects;
- ``registry.py`` — all of them and the DEV / BLIND split;
- ``campaign.py`` — campaigns (CSV + truth JSON), deterministic from a seed;
- ``score.py`` — scores a diagnosis report against the truth;
- ``peers.py`` — SINDy (STLSQ) and eq. 14 + gradient boosting on the same held-out experiments;
- ``plots.py``, ``tables.py`` — the figures and the markdown tables of a run;
- ``runlog.py`` — the resumable log of a sweep.

``BLIND.md`` describes the BLIND half; the method's developer does not read it.
"""
