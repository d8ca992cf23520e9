"""Finds the Python modules generated from proto/orcs/v1/*.proto (job_pb2, result_pb2, broker_pb2).

They are built, not checked in (`ninja -C build orcs_python_proto` writes build/python/orcs/v1/). Looked for, in
this order: the folder named by the environment variable ORCS_PYTHON_PATH; anything already importable as
orcs.v1 (PYTHONPATH); the build/python folder of the source tree this package sits in.
"""

import importlib
import os
import sys

from .errors import SetupError

_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(_PACKAGE_DIR)))  # the source tree: orcs_client/ → python/ → clients/ → root
DEFAULT_PYTHON_PATH = os.path.join(SOURCE_DIR, "build", "python")


def _import_all():
    return tuple(importlib.import_module("orcs.v1." + name) for name in ("job_pb2", "result_pb2", "broker_pb2"))


def load_modules():
    """Returns (job_pb2, result_pb2, broker_pb2). Raises SetupError, one line, when they cannot be found."""
    explicit = os.environ.get("ORCS_PYTHON_PATH", "")
    for folder in [explicit] if explicit else ["", DEFAULT_PYTHON_PATH]:  # "" = whatever sys.path finds
        if folder and not os.path.isfile(os.path.join(folder, "orcs", "v1", "broker_pb2.py")):
            raise SetupError("no generated protobuf modules in %s%s: build them with `ninja -C build "
                             "orcs_python_proto` (it writes build/python) and point ORCS_PYTHON_PATH there"
                             % (folder, " (ORCS_PYTHON_PATH)" if explicit else ""))
        if folder and folder not in sys.path:
            sys.path.insert(0, folder)
        try:
            return _import_all()
        except ImportError as error:
            if (getattr(error, "name", "") or "").startswith("google"):
                raise SetupError("orcs_client needs python3-protobuf (scripts/setup.sh installs it): %s" % error)
            if folder:
                raise SetupError("cannot import the generated modules in %s: %s" % (folder, error))
    raise AssertionError("unreachable")
