"""Readers the tests compare the module with, written from the project's
format pages, not from the module: a .vdb with its UUID masked
(tests/output_digests.py, docs/same-bytes.md) and a Mitsuba .vol
(formats/mitsuba-vol.md)."""

import struct

import numpy as np

UUID_AT, UUID_LEN = 21, 36


def vdb_bytes_but_uuid(path):
    with open(path, "rb") as f:
        data = f.read()
    assert struct.unpack_from("<q", data, 0)[0] == 0x56444220, f"{path}: not an OpenVDB file"
    return data[:UUID_AT] + b"0" * UUID_LEN + data[UUID_AT + UUID_LEN:]


def read_vol(path):
    """A float32 .vol as an array indexed [x, y, z] (+ channel when more than one)."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:4] == b"VOL\x03", f"{path}: not a version 3 .vol"
    encoding, nx, ny, nz, channels = struct.unpack_from("<5i", data, 4)
    assert encoding == 1, f"{path}: encoding {encoding}, not float32"
    values = np.frombuffer(data, dtype="<f4", offset=48).reshape(nz, ny, nx, channels)
    values = values.transpose(2, 1, 0, 3)  # the file runs x fastest
    return values[..., 0] if channels == 1 else values
