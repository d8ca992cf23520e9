"""The wire schema (proto/orcs/v1) for the chaos soak's and the scale benchmark's hand-made peers.

The generated modules come from the build the programs under test came from (BIN/../python, which the build's
`orcs_python_proto` target writes), so that a peer speaks the same schema as the broker it talks to; when that
folder is missing they are generated with protoc from this source tree into a scratch folder.
"""

import importlib
import os
import subprocess
import sys

SOURCE_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PROTOCOL_VERSION = 1


def load(bin_dir, scratch):
    """Returns (job_pb2, result_pb2, status_pb2, broker_pb2)."""
    folder = os.path.join(os.path.dirname(os.path.abspath(bin_dir)), "python")
    if not os.path.isfile(os.path.join(folder, "orcs", "v1", "broker_pb2.py")):
        folder = os.path.join(scratch, "python")
        os.makedirs(folder, exist_ok=True)
        protos = [os.path.join(SOURCE_DIR, "proto", "orcs", "v1", n + ".proto")
                  for n in ("job", "result", "status", "broker")]
        subprocess.run(["protoc", "--python_out=" + folder, "-I", os.path.join(SOURCE_DIR, "proto")] + protos,
                       check=True)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    return tuple(importlib.import_module("orcs.v1." + n) for n in ("job_pb2", "result_pb2", "status_pb2",
                                                                   "broker_pb2"))


def has_field(message_class, name):
    return name in message_class.DESCRIPTOR.fields_by_name
