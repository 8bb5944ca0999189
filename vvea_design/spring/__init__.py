"""The gas spring wing: physics, the frozen design, requirements, the design
file, the optimiser and the paper's reference configurations.

Data flow: ``gas_spring`` (paper eqs 3-7, the linearity metric) ->
``design`` (frozen geometry, strength, mass) -> ``requirements`` (TOML,
constraint margins) -> ``design_file`` (the design JSON) -> ``optimise``
(global search, Pareto fronts, maps); ``curve`` samples a design's force
and pressures over the stroke, ``paper`` holds the paper's Fig. 3-5
configurations and ``plots`` the spring-side figures.
"""
