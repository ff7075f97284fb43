"""The content checksum of a reduced body file, computed from the file alone as
doc/reduced_body_file.md ("Content checksum") defines it, independently of the C++ code
(src/io/reduced_body_file.cc): the tests compare it with the stored one, and use it to play an
attacker who edits a file and writes a matching checksum, which only the physical checks can
then catch.
"""
import hashlib
import struct

import h5py
import numpy as np

_MASK = 0xFFFFFFFFFFFFFFFF
_known = {}  # sha1 of bytes -> FNV-1a: pure Python hashes about 5 MB/s; most items stay unchanged


def fnv1a(data):
    """64-bit FNV-1a of the bytes @p data."""
    key = hashlib.sha1(data).digest()
    if key not in _known:
        h = 0xCBF29CE484222325
        for byte in data:
            h = ((h ^ byte) * 0x100000001B3) & _MASK
        _known[key] = h
    return _known[key]


def _attribute_bytes(value):
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).rstrip(b"\0")
    if isinstance(value, str):
        return value.encode().rstrip(b"\0")
    return struct.pack("<q", int(value))  # integers: int64 little-endian


def _dataset_bytes(dataset):
    kind = dataset.dtype.kind
    if kind == "S":
        return bytes(dataset[()]).rstrip(b"\0")
    if kind == "f":
        return np.ascontiguousarray(dataset[()], dtype="<f8").tobytes()
    return np.ascontiguousarray(dataset[()], dtype="<u4").tobytes()


def content_checksum(f):
    """The checksum (16 hex digits) of the open h5py file @p f."""
    items = {}

    def attributes(path, obj):
        for name, value in obj.attrs.items():
            if not (path == "/" and name == "content_checksum"):
                items[path + "@" + name] = fnv1a(_attribute_bytes(value))

    def visit(name, obj):
        attributes("/" + name, obj)
        if isinstance(obj, h5py.Dataset):
            items["/" + name] = fnv1a(_dataset_bytes(obj))

    attributes("/", f)
    f.visititems(visit)
    keys = sorted(items, key=lambda k: k.encode())
    return "%016x" % fnv1a(b"".join(k.encode() + b"\0" + struct.pack("<Q", items[k]) for k in keys))


def rewrite_checksum(f):
    """Stores the checksum of the file's present contents, as an attacker would."""
    if "content_checksum" in f.attrs:
        del f.attrs["content_checksum"]
    f.attrs["content_checksum"] = np.bytes_(content_checksum(f).encode())


def flip_bits(f, path, count, seed=23):
    """Flips @p count distinct mantissa bits (0 ... 51) of the doubles in dataset @p path, so every
    value stays finite and near its old value: damage only the checksum can see."""
    data = np.array(f[path], dtype="<f8")
    words = data.reshape(-1).view("<u8")
    rng = np.random.default_rng(seed)
    places = rng.choice(words.size * 52, size=count, replace=False)
    for place in places:
        words[place // 52] ^= np.uint64(1) << np.uint64(place % 52)
    f[path][...] = data  # in place, as damage on a disk would be
