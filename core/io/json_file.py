"""JSON files: reading with errors that name the file, writing atomically."""

import json
from dataclasses import MISSING, fields, is_dataclass
from pathlib import Path
from types import UnionType
from typing import Any, TypeVar, get_args, get_origin

from dolphinfit.core.errors import InputError
from dolphinfit.core.io.atomic import atomic_path

T = TypeVar("T")
_TYPE_NAMES = {float: "a number", int: "a whole number", bool: "true or false", str: "text"}


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


def json_field(data: Any, key: str, types: type | tuple[type, ...], where: str) -> Any:
    """``data[key]`` checked against ``types``; InputError naming ``where`` and the key. A
    JSON true or false is no number: booleans pass only where ``types`` names bool."""
    if not isinstance(data, dict) or key not in data:
        raise InputError(f"{where}: missing {key!r}")
    value = data[key]
    allowed = types if isinstance(types, tuple) else (types,)
    if (isinstance(value, bool) and bool not in allowed) or not isinstance(value, types):
        raise InputError(f"{where}: {key!r} has the wrong type ({value!r})")
    return value


def check_schema_version(data: Any, version: int, where: str) -> None:
    """InputError naming ``where`` unless ``data`` is an object of schema ``version``."""
    if not isinstance(data, dict):
        raise InputError(f"{where}: expected a JSON object")
    found = data.get("schema_version")
    if isinstance(found, int) and not isinstance(found, bool) and found > version:
        raise InputError(f"{where}: schema_version {found} was written by a newer dolphinfit "
                         f"(this one reads {version}): update dolphinfit to open it")
    if found != version:
        raise InputError(f"{where}: schema_version {found!r} is not supported (expected "
                         f"{version})")


def dataclass_from_json(cls: type[T], data: Any, what: str) -> T:
    """Rebuild dataclass ``cls`` from its ``asdict`` JSON: nested dataclasses and tuples come
    back as such; unknown keys, missing ones without a default and values of the wrong type
    raise InputError naming ``what`` and the field (the class checks the values' ranges)."""
    if not isinstance(data, dict):
        raise InputError(f"{what}: expected an object, got {type(data).__name__}")
    known = {field.name: field.type for field in fields(cls)}
    unknown = sorted(set(data) - set(known))
    if unknown:
        raise InputError(f"{what}: unknown options {unknown}")
    missing = [field.name for field in fields(cls) if field.name not in data
               and field.default is MISSING and field.default_factory is MISSING]
    if missing:
        raise InputError(f"{what}: missing {missing}")
    values = {}
    for name, value in data.items():
        kind = known[name]
        if is_dataclass(kind):
            value = dataclass_from_json(kind, value, f"{what}.{name}")
        else:
            value = _typed(value, kind, f"{what}: field {name!r}")
        values[name] = value
    return cls(**values)


def read_tagged_dataclass(path: Path, cls: type[T], file_format: str, version: int,
                          what: str) -> T:
    """Dataclass ``cls`` from a file of ``{"format": file_format, "version": version, …its
    fields}``; InputError naming the file when it is another kind of file, another version,
    or a field is missing or of the wrong type (``what`` names the content, e.g. "lens
    model")."""
    doc = read_json(path, f"the {what}")
    if not isinstance(doc, dict) or doc.get("format") != file_format:
        raise InputError(f"{path}: is no {what} (expected format {file_format!r})")
    if doc.get("version") != version:
        raise InputError(f"{path}: {what} version {doc.get('version')!r}; this dolphinfit "
                         f"reads version {version}")
    fields = {name: value for name, value in doc.items() if name not in ("format", "version")}
    return dataclass_from_json(cls, fields, str(path))


def _typed(value: Any, kind: Any, where: str) -> Any:
    """``value`` checked against a field's type (bool, int, float, str, ``X | None``,
    ``tuple[…]`` or ``tuple[X, ...]`` from a JSON list, a dataclass from an object);
    InputError naming ``where`` otherwise. A JSON number passes for a float, a whole one for an
    int; true and false are no numbers."""
    if is_dataclass(kind):
        return dataclass_from_json(kind, value, where)
    if isinstance(kind, UnionType):
        options = get_args(kind)
        if value is None and type(None) in options:
            return None
        kind = next(option for option in options if option is not type(None))
    if get_origin(kind) is tuple:
        items = get_args(kind)
        if len(items) == 2 and items[1] is Ellipsis and isinstance(value, list):
            items = (items[0],) * len(value)   # tuple[X, ...]
        if not isinstance(value, list) or len(value) != len(items):
            raise InputError(f"{where}: expected a list of {len(items)}, got {value!r}")
        return tuple(_typed(item, item_kind, f"{where}[{i}]")
                     for i, (item, item_kind) in enumerate(zip(value, items)))
    allowed = {float: (int, float), int: (int,), bool: (bool,), str: (str,)}.get(kind)
    if allowed is not None and (not isinstance(value, allowed)
                                or (isinstance(value, bool) and kind is not bool)):
        raise InputError(f"{where}: expected {_TYPE_NAMES[kind]}, got {value!r}")
    return value
