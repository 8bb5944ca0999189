"""The actuator wing: ``model`` (paper eqs 8-13, design -> actuator mapping),
``ocp`` (CasADi collocation transcription) and ``studies`` (rest-to-rest
sweeps, Table 5 statistics, safety).
"""
