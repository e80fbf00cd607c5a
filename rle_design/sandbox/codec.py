"""Typed, pickle-free wire format between the parent and the sandboxed child.

A frame is ``MAGIC | u32 header length | u64 payload length | header JSON | payload``. The header is
``{"m": meta, "v": value tree, "b": [buffer lengths]}``; the payload is the raw bytes of the arrays,
concatenated. The value tree uses JSON natively for None, bool, int, float (NaN and infinities
allowed), str and lists (tuples become lists); a JSON object is always a tag:

- ``{"$a": [index, dtype, shape]}`` an ndarray whose C-order bytes are buffer ``index``;
- ``{"$d": [[key, value], ...]}`` a dict with str keys.

Only numeric and boolean dtypes cross the channel, so decoding never creates Python objects from
bytes the child chose. This file is loaded by the child bootstrap by path (``python -I`` has no
package on ``sys.path``), so it imports nothing but the standard library and numpy.
"""

from __future__ import annotations

import functools
import json
import struct
from typing import Any

import numpy as np

MAGIC = b"RLE1"
PREFIX = struct.Struct("<4sIQ")
MAX_DEPTH = 64
_KINDS = "biufc"
_JSON = json.JSONEncoder(separators=(",", ":"))  # one encoder: json.dumps(**kw) builds one per call
_JSON_DECODE = json.JSONDecoder().decode  # str input: json.loads(bytes) first guesses the encoding


class CodecError(ValueError):
    """A value cannot be encoded, or a frame is malformed."""


def _encode(obj: Any, buffers: list[bytes | memoryview], depth: int) -> Any:
    if depth > MAX_DEPTH:
        raise CodecError(f"value nested deeper than {MAX_DEPTH} levels")
    kind = type(obj)
    if kind is float or kind is int or kind is str or kind is bool or obj is None:  # exact types first
        return obj
    if kind is np.ndarray:
        return _encode_array(obj, buffers)
    if kind is list or kind is tuple:
        return [_encode(v, buffers, depth + 1) for v in obj]
    if isinstance(obj, bool | int | float | str):  # subclasses
        return obj
    if isinstance(obj, np.ndarray):
        return _encode_array(obj, buffers)
    if isinstance(obj, np.generic):
        return _encode(obj.item(), buffers, depth + 1)
    if isinstance(obj, list | tuple):
        return [_encode(v, buffers, depth + 1) for v in obj]
    if isinstance(obj, dict):
        items = []
        for k, v in obj.items():
            if not isinstance(k, str):
                raise CodecError(f"dict key {k!r} of type {type(k).__name__} (keys must be str)")
            items.append([k, _encode(v, buffers, depth + 1)])
        return {"$d": items}
    raise CodecError(
        f"value of type {type(obj).__name__} (allowed: None, bool, int, float, str, list, tuple, dict, ndarray)"
    )


def _encode_array(obj: np.ndarray, buffers: list[bytes | memoryview]) -> dict:
    dtype = obj.dtype
    if dtype.kind not in _KINDS or dtype.fields is not None:
        raise CodecError(f"ndarray of dtype {dtype} (only bool, integer, float, complex)")
    arr = obj if obj.ndim and obj.flags.c_contiguous else np.ascontiguousarray(obj)  # 0-d becomes 1-d
    buffers.append(memoryview(arr).cast("B") if arr.size else b"")
    return {"$a": [len(buffers) - 1, dtype.str, list(arr.shape)]}


def encode_frame(meta: dict[str, Any], value: Any = None) -> list[bytes | memoryview]:
    """Frame parts (write them in order) for ``meta`` (plain JSON) and ``value``.

    Raises:
        CodecError: ``value`` holds a type outside the wire format.
    """
    buffers: list[bytes | memoryview] = []
    tree = _encode(value, buffers, 0)
    header = _JSON.encode({"m": meta, "v": tree, "b": [len(b) for b in buffers]}).encode()
    total = sum(len(b) for b in buffers)
    return [PREFIX.pack(MAGIC, len(header), total) + header, *buffers]


def frame_size(parts: list[bytes | memoryview]) -> int:
    """Total bytes of an encoded frame [B]."""
    return sum(len(p) for p in parts)


def parse_prefix(prefix: bytes) -> tuple[int, int]:
    """(header length, payload length) from the 16-byte prefix."""
    magic, n_header, n_payload = PREFIX.unpack(prefix)
    if magic != MAGIC:
        raise CodecError("frame does not start with the protocol magic")
    return n_header, n_payload


def _decode(node: Any, buffers: list[memoryview], depth: int) -> Any:
    if depth > MAX_DEPTH:
        raise CodecError(f"value nested deeper than {MAX_DEPTH} levels")
    kind = type(node)  # json.loads makes exact types only
    if kind is float or kind is int or kind is str or kind is bool or node is None:
        return node
    if kind is list:
        return [_decode(v, buffers, depth + 1) for v in node]
    if kind is dict and len(node) == 1:
        spec = node.get("$a")
        if spec is not None:
            return _decode_array(spec, buffers)
        if "$d" in node and isinstance(node["$d"], list):
            out = {}
            for item in node["$d"]:
                if not (isinstance(item, list) and len(item) == 2 and isinstance(item[0], str)):
                    raise CodecError("malformed dict entry")
                out[item[0]] = _decode(item[1], buffers, depth + 1)
            return out
    raise CodecError("unknown tag in value tree")


@functools.lru_cache(maxsize=64)
def _dtype(dtype_str: str) -> np.dtype:
    """The allowed numeric dtype named ``dtype_str`` (cached: the same few cross on every call)."""
    try:
        dtype = np.dtype(dtype_str)
    except TypeError:
        raise CodecError(f"unknown dtype {dtype_str!r}") from None
    if dtype.kind not in _KINDS or dtype.fields is not None or dtype.subdtype is not None or dtype.hasobject:
        raise CodecError(f"dtype {dtype} is not allowed")
    return dtype


def _decode_array(spec: Any, buffers: list[memoryview]) -> np.ndarray:
    if not (
        isinstance(spec, list) and len(spec) == 3 and isinstance(spec[0], int) and isinstance(spec[1], str)
    ):
        raise CodecError("malformed array tag")
    index, dtype_str, shape = spec
    if not (0 <= index < len(buffers)) or not isinstance(shape, list):
        raise CodecError("array tag refers to a missing buffer")
    if len(dtype_str) > 8 or not all(isinstance(s, int) and s >= 0 for s in shape) or len(shape) > 32:
        raise CodecError("malformed array dtype or shape")
    dtype = _dtype(dtype_str)
    count = 1
    for s in shape:
        count *= s
    buf = buffers[index]
    if count * dtype.itemsize != len(buf):
        raise CodecError(f"array of shape {tuple(shape)} and dtype {dtype} does not match {len(buf)} bytes")
    return np.frombuffer(buf, dtype=dtype, count=count).reshape(shape)


def decode_frame(header: bytes, payload: bytearray) -> tuple[dict[str, Any], Any]:
    """(meta, value) from a header and its payload; arrays are writable views of ``payload``.

    Raises:
        CodecError: the frame is malformed (never executes or unpickles anything).
    """
    try:
        doc = _JSON_DECODE(header.decode())
    except (ValueError, RecursionError) as exc:  # UnicodeDecodeError among them
        raise CodecError(f"header is not JSON: {exc}") from None
    if not (isinstance(doc, dict) and isinstance(doc.get("m"), dict) and isinstance(doc.get("b"), list)):
        raise CodecError("header lacks meta or buffer table")
    lengths = doc["b"]
    if not all(isinstance(n, int) and n >= 0 for n in lengths) or sum(lengths) != len(payload):
        raise CodecError("buffer table does not match the payload length")
    view = memoryview(payload)
    buffers, offset = [], 0
    for n in lengths:
        buffers.append(view[offset : offset + n])
        offset += n
    return doc["m"], _decode(doc.get("v"), buffers, 0)
