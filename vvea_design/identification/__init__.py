"""The identification wing: ``recordings`` (bench recordings reader) ->
``identify`` (paper eq. 14 and extended fits) -> ``diagnose`` (where the model
and the bench disagree, which physics is missing); ``effects`` holds the
candidate physics and ``testbench`` a bench simulator for tests.
"""
