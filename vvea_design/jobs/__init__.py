"""The jobs: one typed function per ``vvea`` command, the steps :func:`vvea_design.pipeline.design_unit`
is made of.

Each job reads its inputs (an object or the file that holds it), checks its options (:class:`OptionError`
names the option) and its output location before any work, does the work, writes its files only when
given ``out`` (whole or not at all, :mod:`vvea_design.outputs`) and returns a typed result (a frozen
dataclass with ``to_dict()``). The command line parses, calls one job and prints its result.

One module per topic:

* :mod:`.spring` - :func:`~.spring.optimise`, :func:`~.spring.spring_report`, :func:`~.spring.check_design`,
  :func:`~.spring.linearity_map`, :func:`~.spring.pareto_front`
* :mod:`.cad` - :func:`~.cad.build_cad` (the CAD set: build, write, drawings, bill of materials)
* :mod:`.bladder` - :func:`~.bladder.check_bladder`
* :mod:`.identification` - :func:`~.identification.identify`, :func:`~.identification.diagnose`
* :mod:`.studies` - :func:`~.studies.run_rest_to_rest`, :func:`~.studies.run_safety`,
  :func:`~.studies.run_design_study`
* :mod:`.common` - what they share (:class:`~.common.OptionError`, inputs, output folders)

The room sits above the wings and the report and below :mod:`vvea_design.pipeline`, which composes the
jobs into the main job; the modules load the CAD kernel and CasADi only when a job runs.
"""

__all__: list[str] = []
