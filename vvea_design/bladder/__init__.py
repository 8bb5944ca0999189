"""The bladder wing: ``membrane`` (axisymmetric hyperelastic membrane FE) and
``check`` (the bladder check of a design against a silicone's allowable
strain).
"""
