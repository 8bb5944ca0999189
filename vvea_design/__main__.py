"""``python -m vvea_design`` runs the ``vvea`` command."""

from .cli.main import main

if __name__ == "__main__":
    main()
