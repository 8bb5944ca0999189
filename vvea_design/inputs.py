"""Input files read safely: one guard before any input file is read, one text decoder, one JSON parser.

Every loader of the toolkit (requirements TOML, design JSON, recordings CSV/Parquet) reads its file through
this module, so every input kind gets the same checks *before* a byte is read:

* the path exists (a missing file, a folder, a FIFO, a device or a socket is named as such: ``/dev/zero`` is
  "a character device, not a regular file", a folder "a folder, not a file");
* its size is below the limit of its kind (:data:`MAX_BYTES`): a 20 GB file is refused for its size, not
  read until memory runs out;
* text is UTF-8 (a byte-order mark allowed); UTF-16 (with or without a byte-order mark) is named as UTF-16,
  other encodings by the first byte that cannot be decoded (line and column);
* JSON is parsed with a bound on nesting (:data:`MAX_JSON_DEPTH`): a file nested 100,000 deep is an error
  naming the file, not a ``RecursionError``.

Each function takes the error class of its caller's input kind (``SpecError``, ``DesignFileError``,
``RecordingsError``), so the message a user reads names the file and what is wrong, and the caller's own
``except`` clause catches it.

Example
-------
>>> from vvea_design.inputs import check_input_file
>>> check_input_file("/dev/zero", "design file")  # doctest: +SKIP
Traceback (most recent call last):
ValueError: design file /dev/zero: is a character device, not a regular file; give the path of a file
"""

from __future__ import annotations

import json
import os
import re
import stat
from pathlib import Path

__all__ = ["MAX_BYTES", "MAX_JSON_DEPTH", "check_input_file", "read_input_bytes", "decode_text", "parse_json",
           "human_bytes"]

#: Largest file each input kind may be, bytes (a requirements file is a page of text; a design file a few
#: tens of kB; a recordings file a campaign of a few million samples).
MAX_BYTES: dict[str, int] = {
    "requirements file": 1 * 2**20,
    "design file": 16 * 2**20,
    "recordings file": 2 * 2**30,
}
#: Deepest nesting a design JSON may have (the real one is 4 deep).
MAX_JSON_DEPTH = 64


def human_bytes(n: int) -> str:
    """A byte count as a reader wants it.

    Parameters
    ----------
    n : int
        Number of bytes.

    Returns
    -------
    str
        ``"512 bytes"``, ``"1.5 MiB"``, ``"20.0 GiB"`` ...
    """
    if n < 1024:
        return f"{n} bytes"
    for unit in ("KiB", "MiB", "GiB", "TiB"):
        n /= 1024
        if n < 1024 or unit == "TiB":
            return f"{n:.1f} {unit}"
    return f"{n} bytes"  # pragma: no cover - unreachable


_KINDS = ((stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def check_input_file(path: str | os.PathLike, what: str, error: type[Exception] = ValueError,
                     max_bytes: int | None = None) -> Path:
    """Raise ``error`` unless ``path`` is an existing regular file of a sensible size; nothing is read.

    Parameters
    ----------
    path : path-like
        The input file.
    what : str
        Its kind, named in messages (``"design file"``); also picks the size limit of :data:`MAX_BYTES`.
    error : type of Exception
        The error class raised (the caller's input kind, a ``ValueError`` subclass).
    max_bytes : int or None
        Size limit in bytes; None: :data:`MAX_BYTES` of ``what`` (no limit for an unknown kind).

    Returns
    -------
    Path
        ``path`` as a Path.

    Raises
    ------
    error
        The path does not exist, is a folder, a FIFO, a device or a socket, or is larger than the limit.
    """
    p = Path(path)
    try:
        st = os.stat(p)  # follows links: a link to a regular file is that file
    except FileNotFoundError:
        if os.path.islink(p):
            raise error(f"{what} {p}: is a broken symbolic link (to {os.readlink(p)}); give the path of a file") from None
        raise error(f"{what} {str(p)!r} not found: it does not exist") from None
    except OSError as exc:
        raise error(f"{what} {p}: cannot be read ({exc.strerror or exc})") from None
    if stat.S_ISDIR(st.st_mode):
        raise error(f"{what} {p}: is a folder, not a file; give the path of the {what}")
    for test, kind in _KINDS:
        if test(st.st_mode):
            raise error(f"{what} {p}: is {kind}, not a regular file; give the path of a file")
    limit = MAX_BYTES.get(what) if max_bytes is None else max_bytes
    if limit is not None and st.st_size > limit:
        raise error(f"{what} {p}: is {human_bytes(st.st_size)} ({st.st_size} bytes), larger than any {what} "
                    f"this tool reads ({human_bytes(limit)}); is it the right file?")
    return p


def read_input_bytes(path: str | os.PathLike, what: str, error: type[Exception] = ValueError,
                     max_bytes: int | None = None) -> bytes:
    """:func:`check_input_file`, then the file's bytes (never more than the limit).

    Parameters
    ----------
    path : path-like
        The input file.
    what : str
        Its kind, named in messages.
    error : type of Exception
        The error class raised.
    max_bytes : int or None
        Size limit in bytes (None: :data:`MAX_BYTES` of ``what``).

    Returns
    -------
    bytes
        The content.

    Raises
    ------
    error
        As :func:`check_input_file`, or the file cannot be read.
    """
    p = check_input_file(path, what, error, max_bytes)
    limit = MAX_BYTES.get(what) if max_bytes is None else max_bytes
    try:
        with open(p, "rb") as fh:
            raw = fh.read(-1 if limit is None else limit + 1)
    except OSError as exc:
        raise error(f"{what} {p}: cannot be read ({exc.strerror or exc})") from None
    if limit is not None and len(raw) > limit:  # it grew since the check
        raise error(f"{what} {p}: is larger than any {what} this tool reads ({human_bytes(limit)})")
    return raw


def _utf16(raw: bytes) -> str | None:
    """``"UTF-16-LE"`` / ``"UTF-16-BE"`` when ``raw`` looks like UTF-16 text (a BOM, or NULs at every other byte)."""
    if raw[:2] == b"\xff\xfe":
        return "UTF-16-LE (with a byte-order mark)"
    if raw[:2] == b"\xfe\xff":
        return "UTF-16-BE (with a byte-order mark)"
    head = raw[:4096]
    if len(head) >= 4:
        odd, even = head[1::2], head[0::2]
        if odd.count(0) > 0.6 * len(odd) and even.count(0) < 0.1 * len(even):
            return "UTF-16-LE (no byte-order mark)"
        if even.count(0) > 0.6 * len(even) and odd.count(0) < 0.1 * len(odd):
            return "UTF-16-BE (no byte-order mark)"
    return None


def decode_text(raw: bytes, path: str | os.PathLike, what: str, error: type[Exception] = ValueError,
                fmt: str = "text") -> str:
    """UTF-8 text of ``raw`` (a byte-order mark dropped); other encodings are an error naming them.

    Parameters
    ----------
    raw : bytes
        The file's content.
    path : path-like
        The file, named in messages.
    what : str
        Its kind, named in messages (``"requirements file"``).
    error : type of Exception
        The error class raised.
    fmt : str
        The format's name in the advice (``"TOML"``, ``"JSON"``, ``"CSV"``).

    Returns
    -------
    str
        The text.

    Raises
    ------
    error
        UTF-16 text (named as such), NUL bytes (not text at all), or a byte that is not UTF-8 (its line,
        column and offset).
    """
    enc = _utf16(raw)
    if enc is not None:
        raise error(f"{path}: is UTF-16 text ({enc}); a {fmt} {what} must be UTF-8 — save it as UTF-8 "
                    f"(e.g. `iconv -f UTF-16 -t UTF-8 {Path(path).name} > {Path(path).stem}-utf8{Path(path).suffix}`)")
    if b"\x00" in raw[:1 << 20]:
        raise error(f"{path}: is not a text file (it holds NUL bytes); expected a {fmt} {what}")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        col = exc.start - (raw.rfind(b"\n", 0, exc.start) + 1) + 1
        raise error(f"{path}: not UTF-8 text: byte 0x{raw[exc.start]:02x} at line {line}, column {col} (byte offset "
                    f"{exc.start}) cannot be decoded; a {fmt} {what} is UTF-8 — save it as UTF-8 (e.g. "
                    f"`iconv -f latin1 -t utf-8`)") from None


_OPEN = re.compile(r'"(?:[^"\\]|\\.)*"|[\[{]|[\]}]')


def _json_depth(text: str, limit: int) -> int:
    """Largest nesting depth of the JSON text (strings skipped), stopping once it exceeds ``limit``."""
    depth = deepest = 0
    for m in _OPEN.finditer(text):
        tok = m.group()
        if tok in "[{":
            depth += 1
            if depth > deepest:
                deepest = depth
                if deepest > limit:
                    return deepest
        elif tok in "]}":
            depth -= 1
    return deepest


class _DuplicateKey(Exception):
    """A JSON object holds a key twice (args: the key, its values in order)."""


def _refuse_duplicate_keys(pairs: list) -> dict:
    out: dict = {}
    for k, v in pairs:
        if k in out:
            raise _DuplicateKey(k, [out[k], v])
        out[k] = v
    return out


def _line_of_second(text: str, key: str) -> str:
    """``, line N`` of the key's second occurrence in ``text`` (empty when it cannot be told)."""
    hits = [m.start() for m in re.finditer(re.escape(json.dumps(key)) + r"\s*:", text)]
    return f", line {text.count(chr(10), 0, hits[1]) + 1}" if len(hits) > 1 else ""


def parse_json(text: str, path: str | os.PathLike, what: str, error: type[Exception] = ValueError,
               max_depth: int = MAX_JSON_DEPTH):
    """Parse JSON text; malformed or absurdly nested text is an error naming the file.

    Parameters
    ----------
    text : str
        The JSON text.
    path : path-like
        The file, named in messages.
    what : str
        Its kind, named in messages.
    error : type of Exception
        The error class raised.
    max_depth : int
        Deepest nesting of objects and arrays accepted.

    Returns
    -------
    object
        The parsed value (``NaN``/``Infinity`` literals are read as floats, as Python's json does).

    Raises
    ------
    error
        Not valid JSON (line and column), nested deeper than ``max_depth``, or an object holding a key twice.
    """
    if _json_depth(text, max_depth) > max_depth:
        raise error(f"{path}: nested more than {max_depth} levels deep; not a {what} (a design file is 4 deep)")
    try:
        return json.loads(text, object_pairs_hook=_refuse_duplicate_keys)
    except _DuplicateKey as dup:
        key, values = dup.args
        raise error(f"{path}: key {key!r} appears twice in one object ({', then '.join(map(repr, values))}"
                    f"{_line_of_second(text, key)}): JSON would keep the last one without a word; remove one "
                    f"(not a valid {what})") from None
    except json.JSONDecodeError as exc:
        raise error(f"{path}: not valid JSON: {exc}") from None
    except RecursionError:  # pragma: no cover - guarded by the depth check
        raise error(f"{path}: nested too deep to be a {what}") from None
