"""Shared test helpers."""

from pathlib import Path

import typer


def make_app(register) -> typer.Typer:
    """A typer app with one topic module's commands registered, as `vvea` would have them.

    The empty callback keeps typer from collapsing a single command into the app itself.
    """
    app = typer.Typer()

    @app.callback()
    def _main():  # pragma: no cover - typer needs a callback to keep sub-commands
        pass

    register(app)
    return app


#: The shared example campaigns (CI clones the repository with shared/ beside it).
SHARED_RECORDINGS = Path(__file__).resolve().parents[2] / "shared" / "recordings"
