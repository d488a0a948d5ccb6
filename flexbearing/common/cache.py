"""Where cached meshes and reduced cages live, and the content hash that keys them."""
from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path


def cache_dir() -> Path:
    """$FLEXBEARING_CACHE, else ~/.cache/flexbearing. Created on first use."""
    root = Path(os.environ.get("FLEXBEARING_CACHE", Path.home() / ".cache" / "flexbearing"))
    root.mkdir(parents=True, exist_ok=True)
    return root


def content_hash(obj) -> str:
    """SHA-256 (first 16 hex digits) of the canonical JSON of obj (dicts sorted, floats repr'd)."""
    text = json.dumps(obj, sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]
