"""A resumable sweep's log: one JSON row per finished campaign, appended as it completes."""

from __future__ import annotations

import json
from pathlib import Path

__all__ = ["RunLog"]


class RunLog:
    """Rows of finished campaigns in a JSON-lines file (``--resume`` keeps the ones without an error)."""

    def __init__(self, path: Path, resume: bool) -> None:
        """Open the log; without ``resume`` an old log is removed.

        Parameters
        ----------
        path : pathlib.Path
            The JSON-lines file.
        resume : bool
            Keep the rows already in it.
        """
        self.path = Path(path)
        self.done: dict[str, dict] = {}
        if resume and self.path.exists():
            for line in self.path.read_text().splitlines():
                row = json.loads(line)
                if "error" not in row:
                    self.done[row["campaign_id"]] = row
        elif self.path.exists():
            self.path.unlink()

    def append(self, _index: int, row: dict) -> None:
        """Append one finished row (a ``parallel_map`` ``on_result`` callback).

        Parameters
        ----------
        _index : int
            Position of the item in the sweep (unused).
        row : dict
            The row; it must carry ``campaign_id``.
        """
        with self.path.open("a") as fh:
            fh.write(json.dumps(row, default=str) + "\n")

    def merged(self, ids, new_rows) -> list[dict]:
        """Rows in the order of ``ids``: the new ones over the kept ones.

        Parameters
        ----------
        ids : iterable of str
            Campaign ids in the wanted order.
        new_rows : list of dict
            Rows just computed.

        Returns
        -------
        list of dict
            One row per id that has one.
        """
        by_id = {**self.done, **{r["campaign_id"]: r for r in new_rows}}
        return [by_id[i] for i in ids if i in by_id]
