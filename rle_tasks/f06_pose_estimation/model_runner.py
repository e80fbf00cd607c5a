"""Verifier-owned wrapper that serves a TorchScript ``model.pt`` under the estimator protocol (variant C).

Runs inside the sandbox (imported by path, standard library, numpy and torch only). At import it
checks the archive's tensor storage size, loads the model with ``torch.jit.load`` on CPU with one
thread, and counts every tensor element (parameters, buffers, tensor attributes) before any
inference; more than 20 M elements refuses the model. ``update`` runs one stateless forward pass:

    model(rgb (1, 3, 240, 320) float in [0, 1], depth (1, 1, 240, 320) [m], valid (1, 1, 240, 320) 0/1)
        -> (1, 6) or (6,): x [m], y [m], theta [rad], logits of T, C, F
"""

import zipfile

import numpy as np

MODEL = "model.pt"
MAX_ELEMENTS = 20_000_000
MAX_STORAGE_BYTES = 8 * MAX_ELEMENTS  # float64 worst case: checked before unpacking anything


def _storage_bytes(path):
    with zipfile.ZipFile(path) as z:
        return sum(i.file_size for i in z.infolist() if "/data/" in i.filename or "/constants/" in i.filename)


def _count(module):
    seen, total = set(), 0
    tensors = list(module.parameters()) + list(module.buffers())
    for t in tensors:
        if id(t) not in seen:
            seen.add(id(t))
            total += t.numel()
    return total


def _load():
    size = _storage_bytes(MODEL)
    if size > MAX_STORAGE_BYTES:
        raise ValueError(f"model.pt stores {size} bytes of tensors, more than {MAX_STORAGE_BYTES}")
    import torch

    torch.set_num_threads(1)
    model = torch.jit.load(MODEL, map_location="cpu")
    n = _count(model)
    if n > MAX_ELEMENTS:
        raise ValueError(f"model.pt holds {n} tensor elements, more than the limit of {MAX_ELEMENTS}")
    model.eval()
    return torch, model, n


_torch, _model, ELEMENTS = _load()


def reset():
    return None


def update(obs):
    torch = _torch
    with torch.inference_mode():
        rgb = torch.from_numpy(np.ascontiguousarray(obs["rgb"])).permute(2, 0, 1)[None].float() / 255.0
        depth = torch.from_numpy(np.ascontiguousarray(obs["depth"], dtype=np.float32))[None, None]
        valid = torch.from_numpy(np.ascontiguousarray(obs["valid"]).astype(np.float32))[None, None]
        out = _model(rgb, depth, valid)
    out = np.asarray(out.detach().numpy(), dtype=np.float64).reshape(-1)
    if out.shape != (6,):
        raise ValueError(f"model output has {out.size} values, expected 6 (x, y, theta, 3 logits)")
    return np.array([out[0], out[1], out[2], float(np.argmax(out[3:6]))])
