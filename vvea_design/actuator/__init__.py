"""The actuator wing: ``model`` (paper eqs 8-13, design -> actuator mapping),
``ocp`` (CasADi collocation transcription), ``multistart`` (one rest-to-rest
case, every setting), ``rest_to_rest`` (grids, the resumable sweep),
``statistics`` (Table 5), ``safety`` (the torque step) and ``figures``.
"""
