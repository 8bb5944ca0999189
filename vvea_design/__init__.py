"""vvea-design: design toolkit for the pneumatic spring-damper unit of a VVEA.

Layers (no import runs upward):

* ground floor  - :mod:`gas_spring` (physics), :mod:`materials`, :mod:`silicones`,
                  :mod:`membrane` (FE), :mod:`recordings`, :mod:`actuator`
* design        - :mod:`design` (frozen geometry), :mod:`spec` (requirements),
                  :mod:`design_io` (the design JSON), :mod:`paper`
* tools         - :mod:`optimise`, :mod:`cad`, :mod:`bladder`, :mod:`effects`,
                  :mod:`identify`, :mod:`diagnose`, :mod:`testbench` (bench
                  simulator), :mod:`ocp`, :mod:`studies_actuator`
* infrastructure- :mod:`parallel` (the one parallel map), :mod:`progress`,
                  :mod:`plots`, :mod:`testing` (pytest helpers)
* top           - :mod:`cli` and the ``cli_*`` modules
"""

__version__ = "0.1.0"
