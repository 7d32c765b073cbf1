"""Where commands write: one rule and one mechanism for every output file and directory.

The rule (README, "Files"): an existing file or directory that a command did not write is
never overwritten; the same command's earlier output is replaced only with ``force=True``
(``--force``); a directory that is not empty and holds no earlier output is refused; the
filesystem root is refused; the path reported is the path written.

How earlier output is recognised:

* **Directories** (``reproduce --out``, ``audit --all --out``, ``fit --out``) carry a manifest,
  :data:`MANIFEST`, a JSON object ``{"tool": "viscontact", "command": ..., "version": ...,
  "files": {name: sha256}}``.  With ``force`` a file is replaced only when it is listed there and
  its content still has the recorded hash: a file the user edited since, or added under one of
  the names the command writes, is never overwritten.  Files of an earlier run that the new run
  does not write are removed (only while unchanged); anything else in the directory is left alone.
  The manifest of reports written before it existed, :data:`LEGACY_MANIFESTS`, lists names only.
  A directory counts as empty when all it holds is other output directories (``audit --all``
  writes into ``viscontact-report/audit`` by default, before or after ``reproduce``).
* **Single files** (``sweep --csv/--json/--plot``, ``collide --plot``, ``dem run``'s log) carry
  a marker in the file: PNG: a ``tEXt`` chunk with the keyword ``viscontact``; CSV: a first line
  ``# written by viscontact COMMAND VERSION``; JSON: a first key ``"written_by": "viscontact
  COMMAND VERSION"``; a LAMMPS log (first line ``LAMMPS (``): the same comment line among its
  first lines, echoed there by LAMMPS from the first line of the input that ``dem run`` wrote
  (:func:`text_marker`; LAMMPS itself writes the log, so only the check applies).

Writing is atomic: a file goes through a temporary sibling and ``os.replace`` (or a hard link,
which never replaces a file that appeared meanwhile); a directory is built in a temporary
directory and moved into place whole (or file by file into an existing one); a failure leaves
nothing behind, not even the parent directories it created.

How a command uses it (``cli/core.py``, ``cli/fit.py``, ``report/build.py`` are examples): check
before any work, write after it, with the command's name (the owner recorded in the marker)::

    check_file(args.plot, "collide", args.force, "--plot", ".png")      # refuses early
    ...
    write_png(args.plot, "collide", args.force, "--plot", lambda tmp: fig.savefig(tmp))

    out = OutputDir(args.out, "fit", args.force, expected=names)        # refuses early
    ...
    with out:                                                            # installs at the end
        (out.staging / "fit.json").write_text(text)
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import shutil
import struct
import tempfile
import zlib
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

__all__ = ["OutputError", "MANIFEST", "LEGACY_MANIFESTS", "PNG_KEY", "OutputDir", "check_file",
           "write_png", "write_text", "write_json", "written_by", "read_manifest", "text_marker",
           "finite_json"]

MANIFEST = ".viscontact-output.json"
LEGACY_MANIFESTS = {".viscontact-report": "reproduce"}
PNG_KEY = b"viscontact"
_PNG_SIG = b"\x89PNG\r\n\x1a\n"
# COMMAND: one or two words ("sweep", "dem run"); the version after it starts with a digit
_COMMAND = r"([a-z][a-z-]*(?: [a-z][a-z-]*)?)\b"
_TEXT_MARK = re.compile(r"# written by viscontact " + _COMMAND)
_JSON_MARK = re.compile(r'\{\s*"written_by":\s*"viscontact ' + _COMMAND)
#: a LAMMPS log begins so; the input's first lines are echoed within its first few lines
_LAMMPS_LOG = "LAMMPS ("
_LAMMPS_ECHO_LINES = 12


def finite_json(obj: Any) -> Any:
    """Replace non-finite floats by None so the output is strict JSON."""
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: finite_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_json(v) for v in obj]
    return obj


class OutputError(ValueError):
    """An output path that must not or cannot be written (the message says what to do)."""


def _version() -> str:
    from .._version import __version__

    return __version__


def _stamp(command: str) -> str:
    return f"viscontact {command} {_version()}"


def text_marker(command: str) -> str:
    """The marker line of a text file written by ``command``: ``# written by viscontact
    COMMAND VERSION`` (the first line of a CSV; the first line of ``dem run``'s LAMMPS input,
    which LAMMPS echoes into the log)."""
    return f"# written by {_stamp(command)}"


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


# --------------------------------------------------------------------------- single files

def written_by(path: str | os.PathLike) -> str | None:
    """The viscontact command whose marker ``path`` carries, or None (not ours, unreadable)."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(4096)
            if head.startswith(_PNG_SIG):
                return _png_marker(fh)
    except OSError:
        return None
    text = head.decode("utf-8", errors="replace")
    m = _TEXT_MARK.match(text) or _JSON_MARK.match(text)
    if m is None and text.startswith(_LAMMPS_LOG):
        lines = text.splitlines()[1:_LAMMPS_ECHO_LINES]
        m = next(filter(None, map(_TEXT_MARK.match, lines)), None)
    return m.group(1) if m else None


def _png_marker(fh) -> str | None:
    """The command in a PNG's ``viscontact`` tEXt chunk (chunks before the image data only)."""
    fh.seek(len(_PNG_SIG))
    while True:
        head = fh.read(8)
        if len(head) < 8:
            return None
        length, kind = struct.unpack(">I4s", head)
        if kind in (b"IDAT", b"IEND") or length > 1 << 16:
            return None
        data = fh.read(length)
        fh.seek(4, os.SEEK_CUR)
        if kind == b"tEXt" and data.startswith(PNG_KEY + b"\0"):
            words = data[len(PNG_KEY) + 1:].decode("latin-1").split()
            return words[1] if len(words) > 1 and words[0] == "viscontact" else None


def _stamp_png(path: Path, command: str) -> None:
    """Insert a ``tEXt`` chunk ``viscontact: viscontact COMMAND VERSION`` after IHDR."""
    data = path.read_bytes()
    if not data.startswith(_PNG_SIG) or data[12:16] != b"IHDR":  # pragma: no cover - a bug
        raise RuntimeError(f"{path} is not a PNG file")
    end_ihdr = 8 + 8 + struct.unpack(">I", data[8:12])[0] + 4
    body = PNG_KEY + b"\0" + _stamp(command).encode("latin-1")
    chunk = struct.pack(">I", len(body)) + b"tEXt" + body + struct.pack(
        ">I", zlib.crc32(b"tEXt" + body) & 0xFFFFFFFF)
    path.write_bytes(data[:end_ihdr] + chunk + data[end_ihdr:])


def check_file(path: str | None, command: str, force: bool, option: str,
               suffix: str | None = None) -> Path:
    """Refuse an output file that must not be written, before any work is done.

    ``option`` names the flag in messages; ``suffix`` (e.g. ``".png"``) is required when given
    (any case); other files are written under exactly the name given.  Returns the path.
    """
    if path is None or not str(path).strip():
        raise OutputError(f"{option} needs a file name")
    target = Path(path)
    if target.is_dir() or str(path).endswith(("/", os.sep)):
        raise OutputError(f"{option} {path} is a directory; give a file name")
    if suffix is not None and target.suffix.lower() != suffix:
        raise OutputError(f"{option} {path}: give a file name ending in {suffix} "
                          f"(the file is written as {suffix[1:].upper()} under the name given)")
    if target.is_symlink() or (os.path.lexists(target) and not target.is_file()):
        raise OutputError(f"{option} {path} exists and is not a regular file; it is never "
                          "overwritten: choose another name")
    parent = target.parent
    if not parent.is_dir():
        raise OutputError(f"cannot write {path}: no directory {parent}")
    if target.exists():
        owner = written_by(target)
        if owner is None:
            raise OutputError(f"{path} exists and was not written by viscontact; it is never "
                              f"overwritten: choose another {option} name")
        if owner != command:
            raise OutputError(f"{path} was written by viscontact {owner}, not {command}; it is "
                              f"never overwritten: choose another {option} name")
        if not force:
            raise OutputError(f"{path} holds an earlier output of viscontact {command}; use "
                              "--force to replace it")
    return target


def _write_file(path: str, command: str, force: bool, option: str, suffix: str | None,
                write: Callable[[Path], None]) -> Path:
    target = check_file(path, command, force, option, suffix)
    try:
        fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=target.suffix,
                                        dir=target.parent)
    except OSError as exc:
        raise OutputError(f"cannot write {path}: {exc.strerror or exc}") from None
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        write(tmp)
        _chmod_default(tmp, 0o666)
        check_file(path, command, force, option, suffix)  # again: the work may have taken long
        try:
            os.link(tmp, target)  # never replaces a file that appeared meanwhile
        except OSError:  # the target exists (ours, checked just now), or no hard links here
            os.replace(tmp, target)
    finally:
        tmp.unlink(missing_ok=True)
    return target


def write_png(path: str, command: str, force: bool, option: str,
              draw: Callable[[Path], Any]) -> Path:
    """``draw(tmp)`` saves a PNG at ``tmp``; it is marked as ``command``'s and moved to ``path``."""
    def write(tmp: Path) -> None:
        draw(tmp)
        _stamp_png(tmp, command)

    return _write_file(path, command, force, option, ".png", write)


def write_text(path: str, command: str, force: bool, option: str, text: str) -> Path:
    """A text file (CSV, Markdown) whose first line is ``# written by viscontact COMMAND ...``."""
    body = f"{text_marker(command)}\n{text}"
    return _write_file(path, command, force, option, None,
                       lambda tmp: tmp.write_text(body, encoding="utf-8"))


def write_json(path: str, command: str, force: bool, option: str, obj: dict[str, Any]) -> Path:
    """A JSON object with the first key ``"written_by": "viscontact COMMAND VERSION"``."""
    text = json.dumps({"written_by": _stamp(command), **obj}, indent=2) + "\n"
    return _write_file(path, command, force, option, None,
                       lambda tmp: tmp.write_text(text, encoding="utf-8"))


def _chmod_default(path: Path, mode: int) -> None:
    """Give a temporary file or directory (private when made) the user's default permissions."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, mode & ~umask)


# --------------------------------------------------------------------------- directories

def read_manifest(out: Path) -> tuple[str, dict[str, str | None]] | None:
    """(command, {file: sha256 or None}) from ``out``'s manifest, or None if it has none."""
    for name, legacy_command in ((MANIFEST, None), *LEGACY_MANIFESTS.items()):
        marker = out / name
        if not marker.is_file():
            continue
        try:
            doc = json.loads(marker.read_text(encoding="utf-8"))
            command = legacy_command or doc["command"]
            files = doc.get("files", {})
            if isinstance(files, list):
                files = dict.fromkeys(files)
            if not isinstance(command, str) or not isinstance(files, dict):
                return None
        except (OSError, ValueError, KeyError, AttributeError, TypeError):
            return None
        return command, {f: h for f, h in files.items() if isinstance(f, str) and _plain_name(f)
                         and (h is None or isinstance(h, str))}
    return None


def _is_output_dir(entry: os.DirEntry) -> bool:
    """A subdirectory holding viscontact output (``audit --all`` writes into the report's)."""
    return entry.is_dir(follow_symlinks=False) and read_manifest(Path(entry.path)) is not None


def _plain_name(name: str) -> bool:
    return bool(name) and "/" not in name and "\\" not in name and name not in (".", "..")


class OutputDir:
    """A directory of output files, written whole or not at all.

    ``OutputDir(path, command, force, expected)`` checks the rule at once (before any work);
    inside ``with out:`` the files are written into ``out.staging`` (plain names, no
    subdirectories); leaving the block without an exception installs them and the manifest,
    with one leaves nothing behind.  ``expected``: names the command will write, checked early.
    """

    def __init__(self, path: str | os.PathLike | None, command: str, force: bool,
                 expected: Iterable[str] = (), option: str = "--out"):
        if path is None or not str(path).strip():
            raise OutputError(f"{option} must name a directory")
        self.out = Path(path)
        self.command = command
        self.force = force
        self.option = option
        if self.out.resolve() == Path(self.out.resolve().anchor):
            raise OutputError(f"{option} {path} is the filesystem root; give a directory of "
                              "its own, such as viscontact-report")
        self.staging: Path = Path()
        self._created: list[Path] = []
        self.old = self._check_dir()
        self._check_names(expected)

    def _check_dir(self) -> dict[str, str | None]:
        out, cmd = self.out, self.command
        if os.path.lexists(out) and not out.is_dir():
            raise OutputError(f"{self.option} {out} exists and is not a directory; choose another "
                              f"{self.option}")
        if not out.exists():
            return {}
        man = read_manifest(out)
        if man is None:
            try:
                empty = not any(e.name != self.staging.name and not _is_output_dir(e)
                                for e in os.scandir(out))
            except OSError as exc:
                raise OutputError(f"cannot read {out}: {exc.strerror or exc}") from None
            if not empty:
                raise OutputError(f"{out} is not empty and holds no earlier output of viscontact "
                                  f"{cmd}; its files are never overwritten: give a new or empty "
                                  f"directory as {self.option}")
            return {}
        owner, files = man
        if owner != cmd:
            raise OutputError(f"{out} holds the output of viscontact {owner}, not {cmd}; it is "
                              f"never overwritten: choose another {self.option}")
        if not self.force:
            raise OutputError(f"{out} already holds an earlier output of viscontact {cmd}; use "
                              "--force to replace it (only its own, unchanged files are replaced)")
        return files

    def _ours(self, name: str) -> bool:
        """Whether ``out/name`` may be replaced: listed, a regular file, unchanged since."""
        target = self.out / name
        if name not in self.old or target.is_symlink() or not target.is_file():
            return False
        recorded = self.old[name]
        try:
            return recorded is None or _sha256(target) == recorded
        except OSError:
            return False

    def _check_names(self, names: Iterable[str]) -> None:
        clash = sorted(n for n in names if os.path.lexists(self.out / n) and not self._ours(n))
        if clash:
            more = " ..." if len(clash) > 4 else ""
            raise OutputError(f"{self.out} has {', '.join(clash[:4])}{more} not written by "
                              f"viscontact {self.command} (or changed since); they are never "
                              f"overwritten: choose another {self.option}")

    def __enter__(self) -> OutputDir:
        try:
            if self.out.exists():
                self.staging = Path(tempfile.mkdtemp(prefix=".viscontact-partial-", dir=self.out))
            else:
                self._created = _make_dirs(self.out.parent)
                self.staging = Path(tempfile.mkdtemp(prefix=f".{self.out.name}.partial-",
                                                     dir=self.out.parent))
            _chmod_default(self.staging, 0o777)
        except OSError as exc:
            self._cleanup()
            raise OutputError(f"cannot write to {self.out}: {exc.strerror or exc}") from None
        return self

    def __exit__(self, kind, exc, tb) -> None:
        try:
            if kind is None:
                self._install()
        finally:
            self._cleanup()

    def _cleanup(self) -> None:
        if self.staging != Path() and self.staging.exists():
            shutil.rmtree(self.staging, ignore_errors=True)
        for d in reversed(self._created):
            try:
                d.rmdir()
            except OSError:
                pass

    def _install(self) -> None:
        names = sorted(p.name for p in self.staging.iterdir())
        if any(not (self.staging / n).is_file() or n == MANIFEST for n in names):  # pragma: no cover
            raise RuntimeError(f"{self.command} staged something other than plain files: {names}")
        manifest = {"tool": "viscontact", "command": self.command, "version": _version(),
                    "files": {n: _sha256(self.staging / n) for n in names}}
        (self.staging / MANIFEST).write_text(json.dumps(manifest, indent=1) + "\n",
                                             encoding="utf-8")
        if not self.out.exists():
            os.rename(self.staging, self.out)
            self._created = []
            return
        self.old = self._check_dir()  # again: the work may have taken long
        self._check_names(names)
        for name in self.old:
            if name not in names and self._ours(name):
                (self.out / name).unlink()
        for legacy in LEGACY_MANIFESTS:
            if (self.out / legacy).is_file():
                (self.out / legacy).unlink()
        for name in names + [MANIFEST]:
            os.replace(self.staging / name, self.out / name)
        self._created = []


def _make_dirs(path: Path) -> list[Path]:
    """mkdir -p, returning the directories created (outermost first)."""
    missing = []
    p = path
    while not p.exists():
        missing.append(p)
        if p.parent == p:
            break
        p = p.parent
    for d in reversed(missing):
        d.mkdir()
    return list(reversed(missing))
