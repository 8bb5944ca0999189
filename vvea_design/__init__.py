"""vvea-design: design toolkit for the pneumatic spring-damper unit of a VVEA.

One subpackage per wing; imports run downwards only:

* ground floor   - :mod:`materials` (structural, silicones)
* spring         - :mod:`spring` (gas-spring physics, design, requirements,
                   design file, optimiser, paper configurations)
* bladder        - :mod:`bladder` (membrane FE, bladder check)
* cad            - :mod:`cad` (build123d parts, mould, export, renders)
* identification - :mod:`identification` (recordings, effects, identify,
                   diagnose, bench simulator)
* actuator       - :mod:`actuator` (model, OCP transcription, studies)
* infrastructure - :mod:`parallel` (the one parallel map), :mod:`progress`,
                   :mod:`testing` (pytest helpers)
* top            - :mod:`cli` (the ``vvea`` command)
"""

__version__ = "0.1.0"
