"""The actuator wing: ``model`` (paper eqs 8-13, design -> actuator mapping),
``ocp`` (CasADi collocation transcription), ``multistart`` (one rest-to-rest
case, every setting), ``rest_to_rest`` (grids, the resumable sweep),
``statistics`` (Table 5), ``safety`` (the torque step), ``verify`` (re-simulation
check), ``figures`` and ``design_study`` (a design against the paper's settings,
fast enough for ``vvea design``).
"""

__all__ = ["run_design_study"]


def __getattr__(name: str):
    """``run_design_study`` on first use (keeps ``import vvea_design.actuator.model`` light)."""
    if name == "run_design_study":
        from .design_study import run_design_study

        return run_design_study
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
