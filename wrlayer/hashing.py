"""SHA-256 fingerprints of input files and texts (recorded in results so a run can be traced to its inputs)."""

from __future__ import annotations

import hashlib
from pathlib import Path

__all__ = ["file_sha256", "file_sha256_or_none", "sha256_hex"]


def sha256_hex(data: bytes | str) -> str:
    """The SHA-256 hex digest of ``data`` (text is encoded as UTF-8)."""
    return hashlib.sha256(data.encode() if isinstance(data, str) else data).hexdigest()


def file_sha256(path: str | Path) -> str:
    """The SHA-256 hex digest of a file's bytes."""
    return sha256_hex(Path(path).read_bytes())


def file_sha256_or_none(path: str | Path) -> str | None:
    """:func:`file_sha256` of ``path`` when it is a file, None otherwise (a scene built in code)."""
    return file_sha256(path) if Path(path).is_file() else None
