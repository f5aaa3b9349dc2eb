"""A task's record, ``task.json`` in its folder: what it was run on (the inputs' content
hashes and options), how it ended, and the figures of both methods for the summary."""

from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.json_file import read_json, write_json

RECORD_JSON = "task.json"
SCHEMA_VERSION = 1
STATUS_COMPLETE = "complete"
STATUS_FAILED = "failed"


@dataclass(frozen=True)
class TaskRecord:
    """``values``: the summary's figures (core/batch/summary.py); ``reused``: this run found
    the task finished on the same inputs and did not run it (not stored)."""

    name: str
    clip: str
    animal_id: str
    status: str
    error: str = ""
    inputs_digest: str = ""
    inputs: dict[str, Any] = field(default_factory=dict)
    values: dict[str, Any] = field(default_factory=dict)
    seconds: float = 0.0
    reused: bool = False


def write_record(folder: Path, record: TaskRecord) -> None:
    """Write ``folder/task.json`` (atomically)."""
    data = {"schema_version": SCHEMA_VERSION, **asdict(record)}
    del data["reused"]
    write_json(folder / RECORD_JSON, data)


def read_record(folder: Path) -> TaskRecord | None:
    """The record in ``folder``; None when there is none or it is not one this version
    wrote (the task then runs again)."""
    path = folder / RECORD_JSON
    if not path.is_file():
        return None
    try:
        data = read_json(path, "the task record")
    except InputError:
        return None
    names = {f.name for f in fields(TaskRecord)} - {"reused"}
    if not isinstance(data, dict) or data.get("schema_version") != SCHEMA_VERSION \
            or not names <= set(data):
        return None
    return TaskRecord(**{name: data[name] for name in names})
