"""vvea-design: design toolkit for the pneumatic spring-damper unit of a VVEA.

Layers (no import runs upward):

* ground floor  - :mod:`gas_spring` (physics), :mod:`materials`, :mod:`recordings`
* design        - :mod:`design` (frozen geometry), :mod:`spec` (requirements),
                  :mod:`design_io` (the design JSON)
* tools         - :mod:`optimise`, :mod:`cad`, :mod:`bladder`, :mod:`identify`,
                  :mod:`diagnose`, :mod:`actuator`, :mod:`ocp`
* infrastructure- :mod:`parallel` (the one parallel map), :mod:`progress`
* top           - :mod:`cli`
"""

__version__ = "0.1.0"
