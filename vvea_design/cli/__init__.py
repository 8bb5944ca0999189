"""The ``vvea`` command line (typer): ``main`` holds the app and the spring
commands; one module per topic registers its commands (``cad``, ``bladder``,
``identify``, ``study``); ``common`` holds the shared error helpers.
"""
