"""The bladder wing: ``membrane`` (axisymmetric hyperelastic membrane FE),
``check`` (the bladder check of a design against a silicone's allowable
strain) and ``result`` (its typed results).
"""
