# SPDX-License-Identifier: BSD-3-Clause
"""The PEP 517 build backend of the nacre Python package: standard library only, so that
`pip install ./python` works offline (pip's isolated build environment has nothing to download:
pyproject.toml's build-system requires nothing and points here through backend-path).

It builds a pure-Python wheel (the `nacre` package, its dist-info: METADATA from pyproject.toml's
[project] table, WHEEL, RECORD, the licence), an sdist (the project directory: pyproject.toml,
_backend/, nacre/, tests/, the licence, PKG-INFO) and an editable wheel (PEP 660: a .pth file
naming this directory). pyproject.toml is read with tomllib (Python >= 3.11), tomli, or, on an
older Python without tomli, the small reader below (the subset pyproject.toml uses: tables,
strings, arrays, inline tables; python/tests/test_packaging.py checks it against tomllib).
"""
import base64
import hashlib
import io
import os
import re
import tarfile
import time
import zipfile

PACKAGE = "nacre"
TAG = "py3-none-any"
# 1980-01-01 (the zip epoch) unless SOURCE_DATE_EPOCH says otherwise: reproducible archives
EPOCH = max(int(os.environ.get("SOURCE_DATE_EPOCH", "315532800")), 315532800)


# ---- pyproject.toml ----------------------------------------------------------------------------

def _load_toml(text):
    try:
        import tomllib
        return tomllib.loads(text)
    except ImportError:
        pass
    try:
        import tomli
        return tomli.loads(text)
    except ImportError:
        return parse_toml_subset(text)


def parse_toml_subset(text):
    """The TOML pyproject.toml uses: comments, [table] / [a.b] headers, key = value with value a
    basic or literal string, an integer, a boolean, an array (over several lines, trailing comma
    allowed) or an inline table. Raises ValueError on anything else."""
    pos, n = 0, len(text)
    root = table = {}

    def skip(newlines=True):
        nonlocal pos
        while pos < n:
            c = text[pos]
            if c in " \t\r" or (newlines and c == "\n"):
                pos += 1
            elif c == "#":
                while pos < n and text[pos] != "\n":
                    pos += 1
            else:
                break

    def fail(what):
        line = text.count("\n", 0, pos) + 1
        raise ValueError(f"pyproject.toml line {line}: {what} (a TOML construct this reader does not know; "
                         "install tomli or use Python >= 3.11)")

    def key():
        nonlocal pos
        m = re.compile(r'[A-Za-z0-9_-]+|"[^"\n]*"').match(text, pos)
        if not m:
            fail("expected a key")
        pos = m.end()
        return m.group(0).strip('"')

    def string():
        nonlocal pos
        q = text[pos]
        pos += 1
        out = []
        while pos < n and text[pos] != q:
            c = text[pos]
            if c == "\n":
                fail("a newline in a string")
            if c == "\\" and q == '"':
                pos += 1
                esc = {"n": "\n", "t": "\t", '"': '"', "\\": "\\"}.get(text[pos] if pos < n else "")
                if esc is None:
                    fail("an escape sequence")
                c = esc
            out.append(c)
            pos += 1
        if pos >= n:
            fail("an unterminated string")
        pos += 1
        return "".join(out)

    def value():
        nonlocal pos
        skip(newlines=False)
        c = text[pos] if pos < n else ""
        if c in "\"'":
            if text.startswith(c * 3, pos):
                fail("a multi-line string")
            return string()
        if c == "[":
            pos += 1
            arr = []
            while True:
                skip()
                if pos < n and text[pos] == "]":
                    pos += 1
                    return arr
                arr.append(value())
                skip()
                if pos < n and text[pos] == ",":
                    pos += 1
                elif pos < n and text[pos] == "]":
                    pos += 1
                    return arr
                else:
                    fail("expected , or ] in an array")
        if c == "{":
            pos += 1
            tab = {}
            skip(newlines=False)
            if pos < n and text[pos] == "}":
                pos += 1
                return tab
            while True:
                skip(newlines=False)
                k = key()
                skip(newlines=False)
                if text[pos] != "=":
                    fail("expected = in an inline table")
                pos += 1
                tab[k] = value()
                skip(newlines=False)
                if pos < n and text[pos] == ",":
                    pos += 1
                elif pos < n and text[pos] == "}":
                    pos += 1
                    return tab
                else:
                    fail("expected , or } in an inline table")
        m = re.compile(r"true|false|[+-]?[0-9]+(?![.eE0-9])").match(text, pos)
        if not m:
            fail("a value")
        pos = m.end()
        word = m.group(0)
        return word == "true" if word in ("true", "false") else int(word)

    while True:
        skip()
        if pos >= n:
            return root
        if text[pos] == "[":
            if text.startswith("[[", pos):
                fail("an array of tables")
            pos += 1
            table = root
            while True:
                skip(newlines=False)
                k = key()
                table = table.setdefault(k, {})
                skip(newlines=False)
                if text[pos] == ".":
                    pos += 1
                    continue
                if text[pos] != "]":
                    fail("expected ] after a table name")
                pos += 1
                break
        else:
            k = key()
            skip(newlines=False)
            if pos >= n or text[pos] != "=":
                fail("expected = after a key")
            pos += 1
            table[k] = value()
        skip(newlines=False)
        if pos < n and text[pos] != "\n":
            fail("text after a value")


def _read(path, mode="rb"):
    with open(path, mode) as f:
        return f.read()


def _project():
    with open("pyproject.toml", encoding="utf-8") as f:
        return _load_toml(f.read())["project"]


def _license_file():
    """The BSD-3-Clause text: beside pyproject.toml (an sdist) or at the repository root."""
    for p in ("LICENSE", os.path.join("..", "LICENSE")):
        if os.path.isfile(p):
            return p
    return None


def metadata_text(project=None):
    """The core metadata (METADATA / PKG-INFO) of pyproject.toml's [project] table."""
    p = project or _project()
    lines = ["Metadata-Version: 2.1", f"Name: {p['name']}", f"Version: {p['version']}"]
    if p.get("description"):
        lines.append(f"Summary: {p['description']}")
    lic = p.get("license")
    if lic:
        lines.append(f"License: {lic if isinstance(lic, str) else lic.get('text', '')}")
    for a in p.get("authors", []):
        if a.get("name"):
            lines.append(f"Author: {a['name']}")
    if p.get("requires-python"):
        lines.append(f"Requires-Python: {p['requires-python']}")
    lines += [f"Classifier: {c}" for c in p.get("classifiers", [])]
    lines += [f"Requires-Dist: {d}" for d in p.get("dependencies", [])]
    for extra, deps in p.get("optional-dependencies", {}).items():
        lines.append(f"Provides-Extra: {extra}")
        lines += [f'Requires-Dist: {d}; extra == "{extra}"' for d in deps]
    return "\n".join(lines) + "\n"


def _dist_info(project):
    return f"{project['name']}-{project['version']}.dist-info"


def _dist_info_files(project):
    files = {
        "METADATA": metadata_text(project),
        "WHEEL": f"Wheel-Version: 1.0\nGenerator: nacre_build\nRoot-Is-Purelib: true\nTag: {TAG}\n",
    }
    lic = _license_file()
    if lic:
        files["LICENSE"] = _read(lic, "r")
    return files


def _package_files():
    """The package's files (relative paths, sorted): every file under nacre/ but caches."""
    out = []
    for d, dirs, files in os.walk(PACKAGE):
        dirs[:] = sorted(x for x in dirs if x != "__pycache__")
        out += [os.path.join(d, f) for f in sorted(files) if not f.endswith((".pyc", ".pyo"))]
    return sorted(p.replace(os.sep, "/") for p in out)


# ---- archives -----------------------------------------------------------------------------------

def _record_hash(data):
    return "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()


def _write_wheel(wheel_directory, entries, project):
    """entries: [(archive path, bytes)]; the dist-info's RECORD is added last."""
    name = f"{project['name']}-{project['version']}-{TAG}.whl"
    record_path = f"{_dist_info(project)}/RECORD"
    record = [f"{p},{_record_hash(d)},{len(d)}" for p, d in entries] + [f"{record_path},,"]
    entries = entries + [(record_path, ("\n".join(record) + "\n").encode())]
    stamp = time.gmtime(EPOCH)[:6]
    tmp = os.path.join(wheel_directory, "." + name + ".tmp")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as z:
        for p, d in entries:
            info = zipfile.ZipInfo(p, date_time=stamp)
            info.external_attr = 0o644 << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, d)
    os.replace(tmp, os.path.join(wheel_directory, name))
    return name


def _dist_info_entries(project):
    di = _dist_info(project)
    return [(f"{di}/{k}", v.encode("utf-8")) for k, v in _dist_info_files(project).items()]


# ---- PEP 517 / PEP 660 hooks --------------------------------------------------------------------

def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def get_requires_for_build_editable(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    project = _project()
    di = os.path.join(metadata_directory, _dist_info(project))
    os.makedirs(di, exist_ok=True)
    for k, v in _dist_info_files(project).items():
        with open(os.path.join(di, k), "w", encoding="utf-8") as f:
            f.write(v)
    return _dist_info(project)


prepare_metadata_for_build_editable = prepare_metadata_for_build_wheel


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    project = _project()
    entries = [(p, _read(p)) for p in _package_files()]
    return _write_wheel(wheel_directory, entries + _dist_info_entries(project), project)


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    """A wheel whose one module file is a .pth naming this directory: `import nacre` then reads
    the source tree (pip install -e ./python)."""
    project = _project()
    pth = (os.path.abspath(os.getcwd()) + "\n").encode()
    return _write_wheel(wheel_directory, [(f"__editable__.{project['name']}.pth", pth)] +
                        _dist_info_entries(project), project)


def build_sdist(sdist_directory, config_settings=None):
    project = _project()
    base = f"{project['name']}-{project['version']}"
    files = ["pyproject.toml"] + _package_files()
    for top in ("_backend", "tests"):
        for d, dirs, fs in os.walk(top):
            dirs[:] = sorted(x for x in dirs if x != "__pycache__")
            files += [os.path.join(d, f).replace(os.sep, "/") for f in sorted(fs) if not f.endswith(".pyc")]
    name = base + ".tar.gz"
    tmp = os.path.join(sdist_directory, "." + name + ".tmp")

    def add(tar, arcname, data):
        info = tarfile.TarInfo(f"{base}/{arcname}")
        info.size, info.mtime, info.mode = len(data), EPOCH, 0o644
        tar.addfile(info, io.BytesIO(data))

    with tarfile.open(tmp, "w:gz", format=tarfile.PAX_FORMAT) as tar:
        for p in sorted(set(files)):
            add(tar, p, _read(p))
        lic = _license_file()
        if lic:
            add(tar, "LICENSE", _read(lic))
        add(tar, "PKG-INFO", metadata_text(project).encode())
    os.replace(tmp, os.path.join(sdist_directory, name))
    return name
