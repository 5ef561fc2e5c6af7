"""SCENE for a job: a .gltf/.glb file (uploaded with its resources) or a scene name.

The rules are the CLI's (client/cli/scene_source.h): a path ending in .gltf/.glb, or naming an
existing file, is a file and must exist; anything else is a scene name under the server's scene
root. A .gltf goes with every resource its buffers[].uri and images[].uri name (data: URIs stay
inline), read relative to its folder and keyed by the uri as written; a uri that is absolute,
has a scheme, or leads outside the folder is refused before anything is sent.
"""

from __future__ import annotations

import json
import os
import struct
from pathlib import Path
from typing import Iterator, List, Union
from urllib.parse import unquote

from ._stubs import pb2
from .errors import PartitaError


def is_scene_file(scene: Union[str, os.PathLike]) -> bool:
    s = str(scene)
    return s.lower().endswith((".gltf", ".glb")) or os.path.isfile(s)


def _external_uris(doc: dict) -> List[str]:
    out, seen = [], set()
    for key in ("buffers", "images"):
        for item in doc.get(key, []) or []:
            uri = item.get("uri") if isinstance(item, dict) else None
            if not isinstance(uri, str) or uri[:5].lower() == "data:" or uri in seen:
                continue
            seen.add(uri)
            out.append(uri)
    return out


def _resolve(scene: Path, folder: Path, uri: str) -> Path:
    def refuse(why: str):
        raise PartitaError(f"scene '{scene}' names resource '{uri}', which {why}")
    if not uri:
        refuse("is empty")
    colon, slash = uri.find(":"), uri.find("/")
    if colon >= 0 and (slash < 0 or colon < slash):
        refuse("is not a relative file name")
    decoded = unquote(uri)
    if decoded.startswith(("/", "\\")) or os.path.isabs(decoded):
        refuse("is an absolute path")
    base = folder.resolve()
    target = (folder / decoded).resolve()
    if target != base and base not in target.parents:
        refuse("lies outside the scene's folder")
    if not target.is_file():
        refuse("does not exist or is not a file")
    return target


def scene_source(scene: Union[str, os.PathLike]):
    """The SceneSource message for `scene`. Raises PartitaError."""
    source = pb2.SceneSource()
    if not is_scene_file(scene):
        if not str(scene):
            raise PartitaError("the scene is empty")
        source.scene_name = str(scene)
        return source
    path = Path(scene)
    if not path.is_file():
        raise PartitaError(f"scene file '{path}' does not exist")
    data = path.read_bytes()
    if data[:4] == b"glTF":
        if len(data) >= 20:
            length, ctype = struct.unpack_from("<II", data, 12)
            if ctype == 0x4E4F534A:
                try:
                    uris = _external_uris(json.loads(data[20:20 + length]))
                except ValueError:
                    uris = []
                if uris:
                    raise PartitaError(f"'{path}' references the external file '{uris[0]}'; a .glb "
                                       "is uploaded alone: embed its resources or use .gltf")
        source.glb = data
        return source
    try:
        doc = json.loads(data)
    except ValueError:
        raise PartitaError(f"scene file '{path}' is not valid glTF JSON") from None
    if not isinstance(doc, dict):
        raise PartitaError(f"scene file '{path}' is not valid glTF JSON")
    folder = path.parent
    for uri in _external_uris(doc):
        source.gltf.resources.add(uri=uri, data=_resolve(path, folder, uri).read_bytes())
    source.gltf.gltf = data
    return source


def add_environment_image(spec, image: Union[str, os.PathLike]) -> None:
    """An environment image for a job whose scene is set: uploaded with a .gltf as one more
    resource ("partita-environment/<name>"), or, with a scene name, the name of an image in that
    scene's folder on the server (the CLI's rule). A .glb upload cannot carry it."""
    which = spec.scene.WhichOneof("source")
    if which == "scene_name":
        spec.environment_file = str(image)
        return
    if which != "gltf":
        raise PartitaError("an environment image goes with a .gltf scene or a scene name, not a .glb")
    path = Path(image)
    try:
        data = path.read_bytes()
    except OSError as e:
        raise PartitaError(f"cannot read environment image '{path}': {e.strerror}") from e
    uri = "partita-environment/" + path.name
    spec.scene.gltf.resources.add(uri=uri, data=data)
    spec.environment_file = uri


_PIECE_BYTES = 1 << 20


def upload_chunks(source) -> Iterator:
    """The UploadChunk messages of an upload (a SceneSource with glb or gltf set): the header
    declaring every file and its size, then the files' bytes in 1 MiB pieces (the scene file,
    then each resource in the header's order)."""
    which = source.WhichOneof("source")
    if which not in ("glb", "gltf"):
        raise PartitaError("only an uploaded .glb or .gltf scene can be streamed")
    header = pb2.UploadHeader()
    if which == "glb":
        header.format = pb2.SCENE_FORMAT_GLB
        files = [source.glb]
    else:
        header.format = pb2.SCENE_FORMAT_GLTF
        files = [source.gltf.gltf]
        for r in source.gltf.resources:
            header.resources.add(uri=r.uri, size=len(r.data))
            files.append(r.data)
    header.scene_bytes = len(files[0])
    yield pb2.UploadChunk(header=header)
    for data in files:
        view = memoryview(data)
        for at in range(0, len(data), _PIECE_BYTES):
            yield pb2.UploadChunk(data=bytes(view[at:at + _PIECE_BYTES]))
