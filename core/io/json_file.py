"""JSON files: reading with errors that name the file, writing atomically."""

import json
from pathlib import Path
from typing import Any

from core.errors import InputError
from core.io.atomic import atomic_path


def read_json(path: Path, what: str) -> Any:
    """The parsed content of ``path``; InputError naming the file if unreadable or not JSON.

    ``what`` names the content in the message, e.g. "the annotation".
    """
    try:
        return json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(f"{path}: cannot read {what} ({exc.strerror})") from exc
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: not valid JSON ({exc})") from exc


def write_json(path: Path, data: Any) -> None:
    """Write ``data`` as indented UTF-8 JSON, atomically (temporary file, then rename)."""
    with atomic_path(Path(path)) as tmp:
        tmp.write_text(json.dumps(data, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
