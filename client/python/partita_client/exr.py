"""A small OpenEXR reader in pure Python + numpy, for the results partitad writes.

Why: OpenImageIO's Python binding (Debian's python3-openimageio) is not guaranteed to be
installed, and partitad's results are plain files: single-part scanline EXRs with float (or
half) channels and ZIP compression, the combined image in R, G, B and one layer per path type
in "<layer>.R/G/B", their order in the string attribute "partita:layers".

Supported: single-part scanline images; channel types UINT, HALF, FLOAT; compression NONE, RLE,
ZIPS, ZIP. Tiled, deep, multi-part files and the other codecs (PIZ, PXR24, B44, DWA) are
refused with a clear error, unless the OpenImageIO binding is importable, which then reads them.
The format, as implemented here, follows the OpenEXR file-layout document
(openexr.com, "OpenEXR File Layout").
"""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Tuple, Union

import numpy as np

_MAGIC = 20000630
_COMPRESSION_NAMES = ["none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"]
_LINES_PER_BLOCK = {0: 1, 1: 1, 2: 1, 3: 16}
_PIXEL_TYPES = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}


class ExrError(ValueError):
    """The file is not an EXR this reader understands."""


@dataclass
class ExrImage:
    width: int
    height: int
    channels: Dict[str, np.ndarray]          # name -> float32 (H, W)
    attributes: Dict[str, object] = field(default_factory=dict)

    def layers(self) -> Dict[str, np.ndarray]:
        """float32 (H, W, 3) arrays: "combined" (R, G, B) first, then each "<layer>.R/G/B"
        triple, in the order of the "partita:layers" attribute, else by first appearance."""
        out: Dict[str, np.ndarray] = {}
        ch = self.channels
        if all(c in ch for c in "RGB"):
            out["combined"] = np.stack([ch["R"], ch["G"], ch["B"]], axis=-1)
        names: List[str] = []
        order = self.attributes.get("partita:layers")
        if isinstance(order, str) and order:
            names = [n for n in order.split(",") if n]
        for c in ch:
            base, _, suffix = c.rpartition(".")
            if base and suffix in ("R", "G", "B") and base not in names:
                names.append(base)
        for n in names:
            if all(f"{n}.{c}" in ch for c in "RGB") and n not in out:
                out[n] = np.stack([ch[f"{n}.R"], ch[f"{n}.G"], ch[f"{n}.B"]], axis=-1)
        if "combined" not in out and ch:
            # Not a partita file: the first three channels (or one, as grey) as "combined".
            keys = list(ch)
            picked = keys[:3] if len(keys) >= 3 else [keys[0]] * 3
            out = {"combined": np.stack([ch[k] for k in picked], axis=-1), **out}
        return out


class _Reader:
    def __init__(self, data: bytes):
        self.data = data
        self.pos = 0

    def take(self, n: int) -> bytes:
        if self.pos + n > len(self.data):
            raise ExrError("truncated EXR file")
        b = self.data[self.pos:self.pos + n]
        self.pos += n
        return b

    def unpack(self, fmt: str):
        size = struct.calcsize(fmt)
        return struct.unpack(fmt, self.take(size))

    def cstring(self) -> str:
        end = self.data.find(b"\0", self.pos)
        if end < 0:
            raise ExrError("truncated EXR header")
        s = self.data[self.pos:end].decode("utf-8", "replace")
        self.pos = end + 1
        return s


def _parse_channels(value: bytes) -> List[Tuple[str, int, int, int]]:
    r = _Reader(value)
    channels = []
    while True:
        name = r.cstring()
        if not name:
            return channels
        pixel_type, _plinear, _r1, _r2, _r3, xs, ys = r.unpack("<iBBBBii")
        channels.append((name, pixel_type, xs, ys))


def _parse_attribute(type_name: str, value: bytes):
    if type_name == "chlist":
        return _parse_channels(value)
    if type_name == "compression":
        return value[0]
    if type_name == "box2i":
        return struct.unpack("<iiii", value)
    if type_name == "string":
        return value.decode("utf-8", "replace")
    if type_name == "int":
        return struct.unpack("<i", value)[0]
    if type_name == "float":
        return struct.unpack("<f", value)[0]
    if type_name == "double":
        return struct.unpack("<d", value)[0]
    if type_name == "lineOrder":
        return value[0]
    return value


def _undo_predictor_and_interleave(t: np.ndarray) -> np.ndarray:
    """ZIP and RLE store bytes split into even/odd halves and delta-coded; undo both."""
    if t.size == 0:
        return t
    d = t.astype(np.int64)
    d[1:] -= 128
    t = (np.cumsum(d) & 0xFF).astype(np.uint8)
    half = (t.size + 1) // 2
    out = np.empty_like(t)
    out[0::2] = t[:half]
    out[1::2] = t[half:]
    return out


def _rle_decode(data: bytes, expected: int) -> np.ndarray:
    out = bytearray()
    i, n = 0, len(data)
    while i < n:
        count = struct.unpack_from("<b", data, i)[0]
        i += 1
        if count < 0:
            out += data[i:i - count]
            i -= count
        else:
            if i >= n:
                raise ExrError("corrupt RLE data")
            out += data[i:i + 1] * (count + 1)
            i += 1
    if len(out) != expected:
        raise ExrError("corrupt RLE data (wrong size)")
    return np.frombuffer(bytes(out), dtype=np.uint8)


def _read_with_oiio(path: Union[str, Path, None], data: bytes) -> ExrImage:
    try:
        import OpenImageIO as oiio  # type: ignore
    except ImportError as e:
        raise ExrError(str(e)) from None
    import os
    import tempfile
    tmp = None
    if path is None:
        fd, tmp = tempfile.mkstemp(suffix=".exr")
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        path = tmp
    try:
        inp = oiio.ImageInput.open(str(path))
        if inp is None:
            raise ExrError(oiio.geterror())
        spec = inp.spec()
        pixels = inp.read_image(0, 0, 0, spec.nchannels, "float")
        inp.close()
        pixels = np.asarray(pixels, dtype=np.float32).reshape(spec.height, spec.width, spec.nchannels)
        channels = {spec.channelnames[c]: pixels[:, :, c].copy() for c in range(spec.nchannels)}
        attrs = {a.name: a.value for a in spec.extra_attribs}
        return ExrImage(spec.width, spec.height, channels, attrs)
    finally:
        if tmp:
            os.unlink(tmp)


def read_exr(source: Union[str, Path, bytes, bytearray]) -> ExrImage:
    """Reads an EXR from a path or from its bytes."""
    path = None
    if isinstance(source, (bytes, bytearray)):
        data = bytes(source)
    else:
        path = Path(source)
        data = path.read_bytes()
    try:
        return _decode(data)
    except _Unsupported as e:
        try:
            return _read_with_oiio(path, data)
        except ExrError:
            raise ExrError(f"{e} (install python3-openimageio to read such files)") from None


class _Unsupported(ExrError):
    pass


def _decode(data: bytes) -> ExrImage:
    r = _Reader(data)
    magic, version = r.unpack("<ii")
    if magic != _MAGIC:
        raise ExrError("not an OpenEXR file")
    flags = version & ~0xFF
    if flags & 0x200:
        raise _Unsupported("tiled EXR files are not supported")
    if flags & 0x800:
        raise _Unsupported("deep EXR files are not supported")
    if flags & 0x1000:
        raise _Unsupported("multi-part EXR files are not supported")
    attrs: Dict[str, object] = {}
    while True:
        name = r.cstring()
        if not name:
            break
        type_name = r.cstring()
        (size,) = r.unpack("<i")
        attrs[name] = _parse_attribute(type_name, r.take(size))
    for required in ("channels", "compression", "dataWindow"):
        if required not in attrs:
            raise ExrError(f"EXR header lacks '{required}'")
    compression = int(attrs["compression"])  # type: ignore[arg-type]
    if compression not in _LINES_PER_BLOCK:
        name = _COMPRESSION_NAMES[compression] if compression < len(_COMPRESSION_NAMES) else str(compression)
        raise _Unsupported(f"EXR compression '{name}' is not supported")
    xmin, ymin, xmax, ymax = attrs["dataWindow"]  # type: ignore[misc]
    width, height = xmax - xmin + 1, ymax - ymin + 1
    if width <= 0 or height <= 0:
        raise ExrError("empty EXR data window")
    channels = attrs["channels"]
    for name, ptype, xs, ys in channels:  # type: ignore[union-attr]
        if ptype not in _PIXEL_TYPES:
            raise ExrError(f"channel '{name}' has an unknown pixel type {ptype}")
        if xs != 1 or ys != 1:
            raise _Unsupported(f"channel '{name}' is subsampled")
    lines = _LINES_PER_BLOCK[compression]
    nblocks = (height + lines - 1) // lines
    offsets = r.unpack(f"<{nblocks}Q")
    row_bytes = sum(_PIXEL_TYPES[p].itemsize for _, p, _, _ in channels) * width  # type: ignore[union-attr]
    planes = {name: np.empty((height, width), np.float32) for name, _, _, _ in channels}  # type: ignore[union-attr]
    for off in offsets:
        if off + 8 > len(data):
            raise ExrError("truncated EXR file (bad offset table)")
        y, size = struct.unpack_from("<ii", data, off)
        payload = data[off + 8:off + 8 + size]
        if len(payload) != size:
            raise ExrError("truncated EXR file")
        y0 = y - ymin
        nlines = min(lines, height - y0)
        if y0 < 0 or nlines <= 0:
            raise ExrError("EXR block outside the data window")
        expected = row_bytes * nlines
        if size == expected or compression == 0:
            raw = np.frombuffer(payload, dtype=np.uint8)
        elif compression == 1:
            raw = _undo_predictor_and_interleave(_rle_decode(payload, expected))
        else:
            try:
                raw = np.frombuffer(zlib.decompress(payload), dtype=np.uint8)
            except zlib.error as e:
                raise ExrError(f"corrupt ZIP block: {e}") from None
            raw = _undo_predictor_and_interleave(raw)
        if raw.size != expected:
            raise ExrError("EXR block has the wrong size")
        pos = 0
        for line in range(nlines):
            for name, ptype, _, _ in channels:  # type: ignore[union-attr]
                dt = _PIXEL_TYPES[ptype]
                n = dt.itemsize * width
                planes[name][y0 + line] = np.frombuffer(raw[pos:pos + n].tobytes(), dtype=dt).astype(np.float32)
                pos += n
    return ExrImage(width, height, planes, attrs)
