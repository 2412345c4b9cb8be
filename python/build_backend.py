"""A PEP 517 build backend for `pip install .`: configures and builds the project's CMake
target prism_python and packs the package folder it makes (build/python/prism) into a wheel.

In the tree, not from an index, so a machine without access to PyPI can install the module:
the only tools it needs (CMake, a compiler, pybind11-dev) are the ones the project's set-up
script installs from Debian. PRISM_BUILD_DIR names a build folder to reuse (configured or
not); otherwise a temporary one is made and removed.
"""

import base64
import hashlib
import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import zipfile

SOURCE = pathlib.Path(__file__).resolve().parents[1]
NAME = "prism"


def _version():
    text = (SOURCE / "CMakeLists.txt").read_text()
    match = re.search(r"project\(prism VERSION ([0-9.]+)", text)
    if not match:
        raise RuntimeError("CMakeLists.txt: no project(prism VERSION ...) line")
    return match.group(1)


def _tag():
    python = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{python}-{python}-{platform}"


def _build(build_dir):
    if not (build_dir / "CMakeCache.txt").exists():
        subprocess.run(["cmake", "-S", str(SOURCE), "-B", str(build_dir), "-G", "Ninja",
                        "-DCMAKE_BUILD_TYPE=Release", "-DPRISM_BUILD_TESTS=OFF",
                        "-DPRISM_BUILD_BENCHMARKS=OFF", f"-DPython3_EXECUTABLE={sys.executable}"],
                       check=True)
    subprocess.run(["cmake", "--build", str(build_dir), "--target", "prism_python", "--parallel",
                    str(os.cpu_count() or 1)], check=True)
    return build_dir / "python" / NAME


def _record_line(path, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{path},sha256={digest},{len(data)}"


def _metadata(version):
    return (f"Metadata-Version: 2.1\nName: {NAME}\nVersion: {version}\n"
            "Summary: Prism: a CPU ray tracer for glTF scenes, built on Embree, from Python\n"
            "Requires-Python: >=3.9\n")


def get_requires_for_build_wheel(config_settings=None):
    return []


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    version = _version()
    tag = _tag()
    given = os.environ.get("PRISM_BUILD_DIR")
    temporary = None if given else tempfile.mkdtemp(prefix="prism-wheel-")
    try:
        package = _build(pathlib.Path(given).resolve() if given else pathlib.Path(temporary))
        dist_info = f"{NAME}-{version}.dist-info"
        files = [(f"{NAME}/{p.name}", p.read_bytes()) for p in sorted(package.iterdir())
                 if p.is_file()]
        files.append((f"{dist_info}/METADATA", _metadata(version).encode()))
        files.append((f"{dist_info}/WHEEL", (
            "Wheel-Version: 1.0\nGenerator: prism build_backend\nRoot-Is-Purelib: false\n"
            f"Tag: {tag}\n").encode()))
        wheel_name = f"{NAME}-{version}-{tag}.whl"
        with zipfile.ZipFile(pathlib.Path(wheel_directory) / wheel_name, "w",
                             zipfile.ZIP_DEFLATED) as wheel:
            record = []
            for path, data in files:
                info = zipfile.ZipInfo(path)
                # Executable bits for the shared objects, read bits for everything.
                info.external_attr = (0o755 if path.endswith(".so") else 0o644) << 16
                info.compress_type = zipfile.ZIP_DEFLATED
                wheel.writestr(info, data)
                record.append(_record_line(path, data))
            record.append(f"{dist_info}/RECORD,,")
            wheel.writestr(f"{dist_info}/RECORD", "\n".join(record) + "\n")
        return wheel_name
    finally:
        if temporary:
            shutil.rmtree(temporary, ignore_errors=True)
