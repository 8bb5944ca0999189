"""Ground floor: material data.

``structural`` (metals and polymers for the housing, with yield strength and
density) and ``silicones`` (casting silicones for the bladder, with their
hyperelastic constants and allowable-strain criteria).
"""
