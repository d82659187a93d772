"""A PEP 517 build backend for the pure-Python package brdffit that needs
nothing but the standard library, so `pip install ./bindings/python` works
without the package index (build isolation installs no build requirements)
and writes nothing into the source tree: the wheel is assembled in memory and
written only to the directory pip asks for.

It builds wheels (and their metadata) only; there is no sdist and no editable
install (put bindings/python on PYTHONPATH for that).
"""

import base64
import hashlib
import os
import zipfile

NAME = "brdffit"
VERSION = "0.1.0"
TAG = "py3-none-any"
_HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_DIST_INFO = "%s-%s.dist-info" % (NAME, VERSION)


def _metadata():
    with open(os.path.join(_HERE, "README.md"), encoding="utf-8") as f:
        readme = f.read()
    return ("Metadata-Version: 2.1\nName: %s\nVersion: %s\n"
            "Summary: Python binding of libbrdffit: fit analytic BRDF models to measured "
            "reflectance\nLicense: MIT\nRequires-Python: >=3.7\nRequires-Dist: numpy\n"
            "Description-Content-Type: text/markdown\n\n%s" % (NAME, VERSION, readme))


def _wheel_file():
    return "Wheel-Version: 1.0\nGenerator: brdffit_wheel\nRoot-Is-Purelib: true\nTag: %s\n" % TAG


def _sources():
    """(archive name, bytes) of every module of the package, sorted."""
    pkg = os.path.join(_HERE, NAME)
    for name in sorted(os.listdir(pkg)):
        if name.endswith(".py") and name != "_install.py":
            with open(os.path.join(pkg, name), "rb") as f:
                yield "%s/%s" % (NAME, name), f.read()


def _record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return "%s,sha256=%s,%d" % (name, digest, len(data))


def get_requires_for_build_wheel(config_settings=None):
    """No build requirements: nothing to download."""
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    """Write the .dist-info directory (METADATA, WHEEL) pip asks for first."""
    target = os.path.join(metadata_directory, _DIST_INFO)
    os.makedirs(target, exist_ok=True)
    for name, text in (("METADATA", _metadata()), ("WHEEL", _wheel_file())):
        with open(os.path.join(target, name), "w", encoding="utf-8") as f:
            f.write(text)
    return _DIST_INFO


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    """Write brdffit-<version>-py3-none-any.whl into ``wheel_directory``."""
    files = list(_sources())
    files.append(("%s/METADATA" % _DIST_INFO, _metadata().encode("utf-8")))
    files.append(("%s/WHEEL" % _DIST_INFO, _wheel_file().encode("utf-8")))
    record = [_record_line(n, d) for n, d in files] + ["%s/RECORD,," % _DIST_INFO]
    files.append(("%s/RECORD" % _DIST_INFO, ("\n".join(record) + "\n").encode("utf-8")))
    wheel = "%s-%s-%s.whl" % (NAME, VERSION, TAG)
    with zipfile.ZipFile(os.path.join(wheel_directory, wheel), "w",
                         zipfile.ZIP_DEFLATED) as zf:
        for name, data in files:
            zf.writestr(zipfile.ZipInfo(name, (1980, 1, 1, 0, 0, 0)), data)
    return wheel
