"""A PEP 517 build backend for the granulab package, standard library only (Python >= 3.11 for tomllib).

Why not setuptools: pip builds in an isolated environment and fetches the backend's requirements from an index;
the lab machines this package is installed on may have none. This backend needs nothing: it zips the package's
files with the metadata of pyproject.toml into a wheel (PEP 427), or writes an editable wheel whose .pth file
points at this folder (PEP 660), or an sdist of the folder.
"""

import base64
import hashlib
import io
import os
import tarfile
import tomllib
import zipfile

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # clients/python
PACKAGE = "granulab"
# A fixed date for the archives' members: two builds of the same files are the same bytes.
EPOCH = (2026, 1, 1, 0, 0, 0)


def _project():
    with open(os.path.join(HERE, "pyproject.toml"), "rb") as f:
        return tomllib.load(f)["project"]


def _dist_info(project):
    return f"{project['name']}-{project['version']}.dist-info"


def _metadata(project):
    lines = ["Metadata-Version: 2.1", f"Name: {project['name']}", f"Version: {project['version']}",
             f"Summary: {project['description']}", f"Requires-Python: {project['requires-python']}"]
    for req in project.get("dependencies", []):
        lines.append(f"Requires-Dist: {req}")
    for extra, reqs in project.get("optional-dependencies", {}).items():
        lines.append(f"Provides-Extra: {extra}")
        lines += [f'Requires-Dist: {r}; extra == "{extra}"' for r in reqs]
    with open(os.path.join(HERE, "README.md"), encoding="utf-8") as f:
        readme = f.read()
    return "\n".join(lines + ["Description-Content-Type: text/markdown", "", readme])


def _entry_points(project):
    scripts = project.get("scripts", {})
    return "[console_scripts]\n" + "".join(f"{name} = {target}\n" for name, target in scripts.items())


def _wheel_name(project):
    return f"{project['name']}-{project['version']}-py3-none-any.whl"


def _write_wheel(directory, project, files):
    """files: [(archive name, bytes)]; adds the dist-info and RECORD."""
    info = _dist_info(project)
    files = list(files) + [
        (f"{info}/METADATA", _metadata(project).encode()),
        (f"{info}/WHEEL", b"Wheel-Version: 1.0\nGenerator: granulab_wheel\nRoot-Is-Purelib: true\nTag: py3-none-any\n"),
        (f"{info}/entry_points.txt", _entry_points(project).encode()),
    ]
    record = []
    for name, data in files:
        digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
        record.append(f"{name},sha256={digest},{len(data)}")
    record.append(f"{info}/RECORD,,")
    files.append((f"{info}/RECORD", ("\n".join(record) + "\n").encode()))
    name = _wheel_name(project)
    with zipfile.ZipFile(os.path.join(directory, name), "w", zipfile.ZIP_DEFLATED) as z:
        for arcname, data in files:
            z.writestr(zipfile.ZipInfo(arcname, EPOCH), data, zipfile.ZIP_DEFLATED)
    return name


def _package_files():
    out = []
    root = os.path.join(HERE, PACKAGE)
    for folder, dirs, names in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for n in sorted(names):
            if n.endswith(".py"):
                path = os.path.join(folder, n)
                with open(path, "rb") as f:
                    out.append((os.path.relpath(path, HERE).replace(os.sep, "/"), f.read()))
    return out


def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def get_requires_for_build_editable(config_settings=None):
    return []


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    return _write_wheel(wheel_directory, _project(), _package_files())


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    project = _project()
    return _write_wheel(wheel_directory, project, [(f"__editable__.{project['name']}.pth", (HERE + "\n").encode())])


def build_sdist(sdist_directory, config_settings=None):
    project = _project()
    base = f"{project['name']}-{project['version']}"
    name = base + ".tar.gz"
    members = [("pyproject.toml", None), ("README.md", None), ("build_backend/granulab_wheel.py", None)]
    members += [(n, None) for n, _ in _package_files()]
    pkg_info = _metadata(project).encode()
    with tarfile.open(os.path.join(sdist_directory, name), "w:gz") as tar:
        for rel, _ in members:
            with open(os.path.join(HERE, rel), "rb") as f:
                data = f.read()
            _add(tar, f"{base}/{rel}", data)
        _add(tar, f"{base}/PKG-INFO", pkg_info)
    return name


def _add(tar, name, data):
    member = tarfile.TarInfo(name)
    member.size, member.mtime, member.mode = len(data), 1767225600, 0o644  # 2026-01-01
    tar.addfile(member, io.BytesIO(data))
