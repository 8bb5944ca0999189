"""A base for the spring wing's typed results: frozen dataclasses with ``to_dict()``.

During the transition from the records-as-dicts these results replaced, a record still answers
``record["key"]`` and ``record.get("key", default)`` with its :meth:`Record.to_dict` content (deprecated:
read the attributes; the command line and the plots read the dictionaries until they are rewritten).
"""

from __future__ import annotations

from dataclasses import fields
from typing import Any

__all__ = ["Record"]


class Record:
    """Mixin of a frozen dataclass result: :meth:`to_dict` and a deprecated read-only mapping view of it."""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready content: every field by name (units in the names).

        Returns
        -------
        dict
            Field name -> value.
        """
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def __getitem__(self, key: str) -> Any:
        """Deprecated: ``self.to_dict()[key]`` (read the attribute instead)."""
        return self.to_dict()[key]

    def get(self, key: str, default: Any = None) -> Any:
        """Deprecated: ``self.to_dict().get(key, default)`` (read the attribute instead).

        Parameters
        ----------
        key : str
            A key of :meth:`to_dict` (unit in the name).
        default : object
            What to return when there is no such key.

        Returns
        -------
        object
            The value, in the unit its name gives, or ``default``.
        """
        return self.to_dict().get(key, default)

    def keys(self):
        """Deprecated: the keys of :meth:`to_dict`.

        Returns
        -------
        KeysView
            The keys (units in the names).
        """
        return self.to_dict().keys()
