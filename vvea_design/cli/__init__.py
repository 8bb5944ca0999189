"""The ``vvea`` command line (typer): ``main`` holds the app and the spring
commands; one module per topic registers its commands (``cad``, ``bladder``,
``identify``, ``study``). Each command parses its options, calls one job of
:mod:`vvea_design.jobs` (or the main job, :mod:`vvea_design.pipeline`) and
prints its result; ``common`` turns a job's errors into messages and exit
codes, ``outputs`` holds ``vvea design``'s unit folder open.
"""
