"""A fingerprint of a media file's content, kept with a project's clip so that opening the
project can tell when the file it measured was replaced or edited since (re-encoded, trimmed,
another clip copied over it under the same name).

Hashing the whole of a multi-gigabyte video would take seconds per gigabyte at every opening.
The fingerprint hashes the size and the first and last MiB instead: a container's header and
index sit there, and a re-encode or a trim changes them and the size. An edit confined to the
middle of a file of the same size would go unseen. A folder of frames is fingerprinted by the
names and sizes of its frame files (not of other files a file browser may leave there).
"""

import hashlib
from pathlib import Path

from dolphinfit.core.io.media import frame_files

CHUNK_BYTES = 1 << 20
VERSION = "v1"   # of the recipe: a fingerprint of another version is not compared


def _file_digest(path: Path, digest: "hashlib._Hash") -> None:
    """The file's size and ends into ``digest`` (not its name: a moved file is the same)."""
    size = path.stat().st_size
    digest.update(f"{size}\n".encode())
    with path.open("rb") as stream:
        digest.update(stream.read(CHUNK_BYTES))
        if size > CHUNK_BYTES:
            stream.seek(max(CHUNK_BYTES, size - CHUNK_BYTES))
            digest.update(stream.read(CHUNK_BYTES))


def media_fingerprint(path: Path) -> str:
    """``VERSION:sha256`` of the media's size and ends (a folder: its files' names and
    sizes); OSError when it cannot be read."""
    digest = hashlib.sha256()
    path = Path(path)
    if path.is_dir():
        for file in frame_files(path):   # the frames only: a thumbnail cache is no change
            digest.update(f"{file.name}\0{file.stat().st_size}\n".encode())
    else:
        _file_digest(path, digest)
    return f"{VERSION}:{digest.hexdigest()}"


def changed_fingerprint(fingerprint: str, path: Path) -> str | None:
    """The fingerprint of ``path`` now, where its content is no longer the one
    ``fingerprint`` was taken of; None when it is (or when ``fingerprint`` is of another
    recipe version, which cannot be compared)."""
    if not fingerprint.startswith(f"{VERSION}:"):
        return None
    now = media_fingerprint(path)
    return None if now == fingerprint else now
