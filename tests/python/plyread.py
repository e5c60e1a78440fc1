# SPDX-License-Identifier: MIT
"""A reader of binary little-endian PLY point clouds, written from the format's definition and
independent of dsm's writer: returns the vertex element as a numpy structured array."""
import numpy as np

_TYPES = {"char": "i1", "uchar": "u1", "short": "<i2", "ushort": "<u2", "int": "<i4", "uint": "<u4",
          "float": "<f4", "double": "<f8", "int8": "i1", "uint8": "u1", "int16": "<i2", "uint16": "<u2",
          "int32": "<i4", "uint32": "<u4", "float32": "<f4", "float64": "<f8"}


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    lines = data[:end].decode("ascii").splitlines()
    if lines[0] != "ply":
        raise ValueError(f"{path}: not a PLY file")
    if lines[1] != "format binary_little_endian 1.0":
        raise ValueError(f"{path}: unsupported format line {lines[1]!r}")
    count, fields, element = 0, [], None
    for line in lines[2:-1]:
        words = line.split()
        if words[0] == "element":
            element = words[1]
            if element == "vertex":
                count = int(words[2])
            elif int(words[2]) != 0:
                raise ValueError(f"{path}: element {element} is not read here")
        elif words[0] == "property" and element == "vertex":
            if words[1] == "list":
                raise ValueError(f"{path}: list properties are not read here")
            fields.append((words[2], _TYPES[words[1]]))
    dtype = np.dtype(fields)
    body = data[end:]
    if len(body) != count * dtype.itemsize:
        raise ValueError(f"{path}: {len(body)} bytes of rows, expected {count} x {dtype.itemsize}")
    return np.frombuffer(body, dtype=dtype, count=count)
