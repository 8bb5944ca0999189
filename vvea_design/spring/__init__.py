"""The gas spring wing: physics, the frozen design, its layouts, requirements, the optimisation problem,
the design file, the optimiser, the studies and the paper's reference configurations.

Data flow: ``gas_spring`` (paper eqs 3-7, the linearity metric) -> ``layouts`` (one module per layout
variant, a registry) -> ``derive`` (every derived quantity, vectorised: geometry, sized walls, stresses,
masses) -> ``design`` (the frozen design) -> ``requirements`` (the spec, its TOML file) -> ``problem``
(a design or a population against the requirements: margins, feasibility) -> ``design_file`` (the design
JSON) -> ``optimise`` (the global search and its polish) -> ``studies`` (Pareto fronts, maps, the gas bound
and capacity); ``parameters`` holds the fixed parameters, ``curve`` samples a design's force and pressures
over the stroke, ``paper`` holds the paper's Fig. 3-5 configurations and ``plots`` the spring-side figures.
"""
