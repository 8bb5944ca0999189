"""Identification of the paper's eq. 14: fit, Table 3, error band, figures and files.

The paper (section 4) fits ::

    f = g p2 x + L(γ) ẋ + C sign(ẋ)                      (eq. 14)

by least squares (eq. 15) and lists g, C (its "B") and one L per valve in
Table 3. Here it is solved exactly by bounded linear least squares (g, C,
L >= 0, :mod:`~vvea_design.identification.fitting`) with cluster-robust
uncertainties; :func:`write_identification` writes Table 3, the JSON summary
and Figs 10/11 (:mod:`~vvea_design.identification.plots`) and returns the
summary as an :class:`Identification`. The extended models of the diagnosis
(eq. 14 plus effects) use the same engine (:mod:`~vvea_design.identification.diagnose`).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from .fit_data import REST_REASON, FitData
from .fitting import ModelFit, fit_model
from .identifiability import Identifiability, identifiability
from .plots import Fig11Example, plot_fig10, plot_fig11
from .recordings import Recordings

__all__ = [
    "PAPER_TABLE3",
    "PAPER_ERROR_BAND_PCT",
    "EQ14_MODEL",
    "fit_eq14",
    "table3",
    "error_band_pct",
    "format_table3",
    "Table3Entry",
    "Identification",
    "write_identification",
]

#: Table 3 of the paper (value per parameter name).
PAPER_TABLE3: dict[str, float] = {
    "g": 23.31,
    "C": 125.5,
    "L(50)": 0.4,
    "L(80)": 0.5,
    "L(100)": 7.1,
    "L(104)": 15.1,
    "L(106)": 25.3,
    "L(108)": 40.6,
    "L(109)": 52.7,
    "L(110)": 85.2,
    "L(120)": 1024.7,
}
#: The paper's error band of eq. 14 against its measurements (% of nominal force).
PAPER_ERROR_BAND_PCT = (-9.5, 12.0)
#: The model of the identification, as the summary writes it.
EQ14_MODEL = "eq14: f = g p2 x + L(gamma) xdot + C sign(xdot)"


def fit_eq14(rec: Recordings | FitData) -> ModelFit:
    """Fit the paper's eq. 14 (g, C, one L per valve) to a campaign.

    Parameters
    ----------
    rec : Recordings or FitData

    Returns
    -------
    ModelFit
        Parameters ``g`` (N/mm/MPa), ``C`` (N), ``L(γ)`` (N s/mm) with
        cluster-robust standard errors.
    """
    D = rec if isinstance(rec, FitData) else FitData.from_recordings(rec)
    return fit_model(D, ())


def table3(fit: ModelFit) -> pd.DataFrame:
    """Table 3's layout: parameter, unit, value, standard error, paper value.

    The paper calls the Coulomb friction ``B`` in Table 3 and ``C`` in eq. 14.

    Parameters
    ----------
    fit : ModelFit
        A fit with the eq.-14 group (e.g. from :func:`fit_eq14`).

    Returns
    -------
    pandas.DataFrame
        Columns ``parameter``, ``unit`` (N/mm/MPa, N, N s/mm), ``value``,
        ``std_error`` (same unit) and ``paper`` (Table 3's value, NaN if none).
    """
    rows = []
    sl = fit.groups["eq14"]
    for q, v, s in zip(fit.params[sl], fit.theta[sl], fit.se[sl]):
        name = "B (=C)" if q.name == "C" else q.name
        rows.append(
            dict(parameter=name, unit=q.unit, value=float(v), std_error=float(s), paper=PAPER_TABLE3.get(q.name, np.nan))
        )
    return pd.DataFrame(rows)


def format_table3(df: pd.DataFrame) -> str:
    """Plain-text rendering of :func:`table3` (Parameter / Unit / Value ± se / Paper).

    Parameters
    ----------
    df : pandas.DataFrame
        Output of :func:`table3`.

    Returns
    -------
    str
        One header line and one line per parameter, values with 2 decimals in their units.
    """
    lines = [f"{'Parameter':<10} {'Unit':<10} {'Value':>22} {'Paper':>9}"]
    for r in df.itertuples():
        val = f"{r.value:10.2f} ± {r.std_error:<8.2f}"
        pap = "" if not np.isfinite(r.paper) else f"{r.paper:9.2f}"
        lines.append(f"{r.parameter:<10} {r.unit:<10} {val:>22} {pap:>9}")
    return "\n".join(lines)


def error_band_pct(D: FitData, force_model_N: np.ndarray) -> tuple[float, float]:
    """Model error (model - measured) in % of the nominal force, min and max.

    The nominal force of an experiment is its largest measured |force|; the
    paper's band for eq. 14 is -9.5 % ... +12 %.

    Parameters
    ----------
    D : FitData
        The campaign (measured force in N, experiment bounds).
    force_model_N : numpy.ndarray, shape (D.n,)
        Model force per sample, N.

    Returns
    -------
    lowest, highest : float
        Smallest and largest model error, % of the experiment's nominal force.
    """
    nom = np.zeros(D.n)
    for e in range(D.n_exp):
        a, b = D.bounds[e], D.bounds[e + 1]
        nom[a:b] = np.max(np.abs(D.y[a:b]))
    err = 100.0 * (force_model_N - D.y) / nom
    return float(err.min()), float(err.max())


@dataclass(frozen=True)
class Table3Entry:
    """One parameter of Table 3 in the summary: value and standard error in ``unit``, the paper's value."""

    value: float
    std_error: float | None  #: None where the recordings do not determine it (see ``identifiability``)
    unit: str
    paper: float | None  #: Table 3's value; None where the paper has none

    def to_dict(self) -> dict:
        """The entry as JSON.

        Returns
        -------
        dict
            ``value``, ``std_error`` (in ``unit``; None where not determined), ``unit`` and ``paper`` (Table 3's
            value in ``unit``, None where the paper has none).
        """
        return dict(value=self.value, std_error=self.std_error, unit=self.unit, paper=self.paper)


@dataclass(frozen=True)
class Identification:
    """What :func:`write_identification` found: Table 3, the error band, identifiability, the files written.

    :meth:`to_dict` is ``identification.json``.
    """

    source: str  #: the recordings file
    rows_read: int
    rows_left_out: int  #: samples at rest (see ``rows_left_out_reason``)
    n_experiments: int
    velocity_fallback_experiments: int  #: experiments whose velocity came from the Savitzky-Golay fallback
    parameters: dict  #: Table3Entry by Table 3's parameter name (``g``, ``B (=C)``, ``L(γ)``)
    rmse_N: float  #: in-sample RMS residual, N
    error_band_pct: tuple  #: (lowest, highest) model error, % of the experiment's nominal force
    identifiability: Identifiability
    notes: tuple  #: what the user must be told (how the file was read, identifiability)
    fig11: Fig11Example | None  #: the experiment Fig. 11 draws (None without figures)
    files: tuple  #: names of the files written, relative to the output folder
    model: str = EQ14_MODEL
    rows_left_out_reason: str = REST_REASON
    residual_sign: str = "figures plot measurement - model"

    def to_dict(self) -> dict:
        """The summary as JSON (``identification.json``).

        Returns
        -------
        dict
            The source, the model, row and experiment counts, ``parameters`` (Table 3, values in their units),
            ``rmse_N`` (N), ``error_band_pct`` (ours and the paper's, % of nominal force), ``identifiability``,
            ``notes``, the residual sign, ``fig11`` and ``files``.
        """
        return dict(
            source=self.source,
            model=self.model,
            rows_read=self.rows_read,
            rows_left_out=self.rows_left_out,
            rows_left_out_reason=self.rows_left_out_reason,
            n_experiments=self.n_experiments,
            velocity_fallback_experiments=self.velocity_fallback_experiments,
            parameters={k: v.to_dict() for k, v in self.parameters.items()},
            rmse_N=self.rmse_N,
            error_band_pct=dict(ours=list(self.error_band_pct), paper=list(PAPER_ERROR_BAND_PCT)),
            identifiability=self.identifiability.to_dict(),
            notes=list(self.notes),
            residual_sign=self.residual_sign,
            fig11=self.fig11.to_dict() if self.fig11 is not None else None,
            files=list(self.files),
        )


def _fig10_name(p2: float) -> str:
    """File name of Fig. 10 for one pressure (``2.5`` -> ``..._p2_2p5MPa.png``)."""
    return f"fig10_model_vs_measurement_p2_{float(p2):g}MPa.png".replace(".", "p", 1) if "." in f"{float(p2):g}" else \
        f"fig10_model_vs_measurement_p2_{float(p2):g}MPa.png"


def _num(v):
    return None if v is None or not np.isfinite(v) else float(v)


def write_identification(rec: Recordings, out_dir: str | Path, fit: ModelFit | None = None, figures: bool = True) -> Identification:
    """Fit eq. 14 and write Table 3 (CSV), a JSON summary and Figs 10/11 (PNG).

    Parameters
    ----------
    rec : Recordings
        The campaign as read.
    out_dir : str or pathlib.Path
        Created if missing. Files: ``table3.csv``, ``identification.json``,
        one ``fig10_model_vs_measurement_p2_<p>MPa.png`` per charge pressure,
        ``fig11_force_displacement.png``.
    fit : ModelFit, optional
        A precomputed eq.-14 fit.
    figures : bool
        Draw Figs 10 and 11 (skip for speed when only numbers are needed).

    Returns
    -------
    Identification
        The summary (:meth:`Identification.to_dict` is ``identification.json``). ``identifiability`` says
        which parameters the data cannot separate (their ``std_error`` is None); ``notes`` collects what
        the user must be told (how the file was read, identifiability).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    D = FitData.from_recordings(rec)
    fit = fit or fit_model(D, ())
    ident = identifiability(fit, D)
    tab = table3(fit)
    bad = ident.unreliable_parameters
    unrel = (not ident.errors_reliable) | tab["parameter"].map(lambda n: ("C" if n == "B (=C)" else n) in bad)
    tab.loc[unrel, "std_error"] = np.nan
    tab.to_csv(out / "table3.csv", index=False)
    fmod = fit.predict(D)
    band = error_band_pct(D, fmod)
    f11 = None
    files = ["table3.csv", "identification.json"]
    for old in out.glob("fig10_model_vs_measurement*.png"):  # never leave a figure of an earlier run beside the new ones
        old.unlink()
    if figures:
        import matplotlib.pyplot as plt

        for p2 in sorted(rec.experiments["p2_MPa"].unique()):
            fig = plot_fig10(rec, D, fmod, float(p2))
            name = _fig10_name(float(p2))
            fig.savefig(out / name, dpi=100)
            plt.close(fig)
            files.append(name)
        fig, f11 = plot_fig11(rec, D, fmod)
        fig.savefig(out / "fig11_force_displacement.png", dpi=100)
        plt.close(fig)
        files.append("fig11_force_displacement.png")
    result = Identification(
        source=rec.source,
        rows_read=rec.rows_read,
        rows_left_out=D.rows_left_out,
        n_experiments=rec.n_experiments,
        velocity_fallback_experiments=rec.n_savgol,
        parameters={r.parameter: Table3Entry(float(r.value), _num(r.std_error), r.unit, _num(r.paper)) for r in tab.itertuples()},
        rmse_N=fit.rmse_N,
        error_band_pct=tuple(band),
        identifiability=ident,
        notes=tuple(rec.notes) + tuple(ident.messages),
        fig11=f11,
        files=tuple(files),
    )
    (out / "identification.json").write_text(json.dumps(result.to_dict(), indent=2, allow_nan=False, default=_num))
    return result
