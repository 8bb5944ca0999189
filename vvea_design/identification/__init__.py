"""The identification wing, one concept per module, in the order the data flows:

- ``recordings`` -- the bench recordings reader (exchange format, velocity from the motion profile);
- ``fit_data`` -- a campaign's samples as arrays for fitting, and the cache of what is computed from them;
- ``signals`` -- operators on the samples (low-pass, stop operator, filters on a finer time grid);
- ``effects/`` -- the physics eq. 14 leaves out: ``base`` (the Effect object and the registry), one
  module per catalogue effect or discovered family, each registering itself;
- ``design``, ``least_squares``, ``fitting`` -- the design matrix, bounded least squares from
  per-experiment blocks, the fitted model (shape search, contexts, cluster-robust errors);
- ``identifiability`` -- what the recordings can separate;
- ``identify`` -- the paper's eq. 14: Table 3, the error band, the files;
- ``settings``, ``selection``, ``noise``, ``report``, ``plots`` -- the diagnosis's stages (split,
  forward/backward selection and final fits; noise floor, residual map, learner check), its typed report
  and summary, the figures;
- ``diagnose`` -- the diagnosis chained and written.

The bench simulators that prove the method live outside the library (the ``vvea_benches`` distribution
in ``benches/``).
"""
