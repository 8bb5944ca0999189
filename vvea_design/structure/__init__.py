"""FE verification of the unit's pressure-bearing pieces: axisymmetric linear elasticity (scikit-fem) on the
meridian sections of the CAD's solids (meshed with gmsh).

Data flow: the CAD model (:class:`~vvea_design.cad.assembly.CadModel`) -> each piece's meridian section
(:mod:`.section`: the solid cut by a half-plane clear of its non-axisymmetric holes, sharp internal corners
rounded) -> a quadratic triangle mesh refined at the corners (:mod:`.meshing`) -> its surface labelled by what
it touches and its joint's bearing face (:mod:`.surroundings`, :mod:`.pieces`, :mod:`.model`) -> solved per
load case (:mod:`.loads`, :mod:`.elasticity`) -> per wall of the design the peak stress, where, the nominal
stress and the closed form beside it (:mod:`.evaluate`) -> :func:`check_structure`'s typed result
(:mod:`.check`) and the stress-field pictures (:mod:`.figures`). :mod:`.verification` holds the FE against
Lamé and the plate formulas; :mod:`.concentration` the stress-concentration factors fitted from FE that the
spring sizing reads as data.

Units: mm, MPa, N.
"""

from .check import CRITERIA, CaseCheck, PieceCheck, StructureResult, WallCheck, check_structure
from .elasticity import AxiProblem, AxiSolution, solve_axisymmetric, tresca, von_mises
from .loads import CASE_POSITION, LoadCase, default_load_cases
from .meshing import MeshSpec, mesh_section
from .section import DEFAULT_CORNER_RADIUS_MM, MeridianSection, section_from_outline, section_of_solid

__all__ = [
    "check_structure", "StructureResult", "WallCheck", "CaseCheck", "PieceCheck", "CRITERIA",
    "LoadCase", "default_load_cases", "CASE_POSITION",
    "MeshSpec", "mesh_section", "MeridianSection", "section_of_solid", "section_from_outline",
    "DEFAULT_CORNER_RADIUS_MM", "AxiProblem", "AxiSolution", "solve_axisymmetric", "von_mises", "tresca",
]
