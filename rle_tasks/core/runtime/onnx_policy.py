"""Loading a submitted ONNX policy as untrusted data, with a declared signature.

The policy-learning families take a network as an ``.onnx`` file. ``load_onnx_policy`` treats the
file as hostile: it must be a regular file inside the submission directory (a symlink may not lead
out), at most ``OnnxSignature.max_bytes`` long, self-contained (external-data references are
refused, so the model cannot make the runtime read other files), valid for ``onnx.checker``, and its
input and output names, element types and static shapes must match the declaration. Inference runs
in this process on ``onnxruntime``'s CPU provider with one intra-op and one inter-op thread; a call
past ``timeout_s`` is stopped through ``RunOptions.terminate``. Every problem is a ``PolicyFault``
with an ``onnx.*`` code (``POLICY_FAULT_CODES``).

``onnx`` and ``onnxruntime`` come with the ``learn`` (and ``dev``) extra and are imported lazily.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rle_design.errors import RleError
from rle_design.excerpt import excerpt
from rle_tasks.core.runtime.policy import PolicyFault
from rle_tasks.core.runtime.protocol import Dim

INSTALL_HINT = "pip install 'rle-bench[learn]'"
_DTYPES = {"tensor(float)": np.float32, "tensor(double)": np.float64}


@dataclass(frozen=True)
class TensorSpec:
    """One declared input or output.

    Attributes:
        name: Tensor name in the graph.
        shape: Dimensions: sizes, symbols resolved from ``dims`` at load, or None (any size).
    """

    name: str
    shape: tuple[Dim, ...]


@dataclass(frozen=True)
class OnnxSignature:
    """What a submitted ONNX policy must look like.

    Attributes:
        inputs: Declared inputs (float32 or float64 tensors).
        outputs: Declared outputs (float32 or float64 tensors), checked for shape and finiteness.
        max_bytes: Largest accepted file [B].
        timeout_s: Wall-clock cap of one inference [s].
    """

    inputs: tuple[TensorSpec, ...]
    outputs: tuple[TensorSpec, ...]
    max_bytes: int = 16 << 20
    timeout_s: float = 1.0


def _resolve(spec: TensorSpec, dims: Mapping[str, int]) -> tuple[int | None, ...]:
    out: list[int | None] = []
    for d in spec.shape:
        if isinstance(d, str):
            if d not in dims:
                raise RleError(
                    f"tensor '{spec.name}': dimension '{d}' has no value. Known dimensions: "
                    f"{', '.join(sorted(dims)) or '(none)'}",
                    code="policy.dims",
                )
            out.append(int(dims[d]))
        else:
            out.append(d)
    return tuple(out)


def _fmt(shape) -> str:
    return "(" + ", ".join("any" if not isinstance(d, int) else str(d) for d in shape) + ")"


def _compatible(got, expected: tuple[int | None, ...]) -> bool:
    """Same rank and no fixed size that differs (symbolic sizes of the model are checked per call)."""
    return len(got) == len(expected) and all(
        not isinstance(g, int) or e is None or g == e for g, e in zip(got, expected)
    )


def _import():
    try:
        import onnx
        import onnxruntime
    except ImportError as exc:
        raise RleError(
            f"ONNX policies need onnx and onnxruntime, which are not installed: {INSTALL_HINT}",
            code="onnx.missing_dependency",
        ) from exc
    return onnx, onnxruntime


def _tensors(model):
    """Every tensor stored in the model: initializers and attribute tensors, subgraphs and functions."""
    graphs = [model.graph]
    nodes = [n for f in model.functions for n in f.node]
    while graphs or nodes:
        if graphs:
            g = graphs.pop()
            yield from g.initializer
            yield from (s.values for s in g.sparse_initializer)
            nodes.extend(g.node)
            continue
        for a in nodes.pop().attribute:
            if a.HasField("t"):
                yield a.t
            yield from a.tensors
            if a.HasField("g"):
                graphs.append(a.g)
            graphs.extend(a.graphs)


def _read(path: Path, root: Path, max_bytes: int) -> tuple[bytes, str]:
    rel = str(path)
    base = root.resolve()
    full = (root / path).resolve()  # follows symlinks: a link leading out is refused below
    if not full.is_relative_to(base):
        raise PolicyFault("onnx.path", f"{rel}: resolves outside the submission directory", path=rel)
    if not full.is_file():
        raise PolicyFault("onnx.path", f"{rel}: not a regular file in the submission directory", path=rel)
    rel = str(full.relative_to(base))
    with open(full, "rb") as fh:
        data = fh.read(max_bytes + 1)
    if len(data) > max_bytes:
        raise PolicyFault("onnx.size", f"{rel}: larger than the cap of {max_bytes} bytes", path=rel)
    return data, rel


class OnnxPolicy:
    """A loaded, checked ONNX policy (build it with ``load_onnx_policy``).

    Attributes:
        path: The file, relative to the submission directory.
        signature: The declaration it was checked against.
    """

    def __init__(self, session, signature: OnnxSignature, dims: Mapping[str, int], path: str) -> None:
        self.path = path
        self.signature = signature
        self._session = session
        self._inputs = {s.name: _resolve(s, dims) for s in signature.inputs}
        self._outputs = {s.name: _resolve(s, dims) for s in signature.outputs}
        self._dtypes = {i.name: _DTYPES[i.type] for i in session.get_inputs()}
        self._order = [o.name for o in session.get_outputs() if o.name in self._outputs]

    def run(self, feeds: Mapping[str, Any]) -> dict[str, np.ndarray]:
        """One inference: declared inputs in, declared outputs (float64) out.

        Raises:
            PolicyFault: ``onnx.run`` (runtime failure), ``onnx.timeout``, ``onnx.shape``, ``onnx.nonfinite``.
            RleError: ``policy.bad_input`` when the inputs do not match the declaration (a verifier bug).
        """
        arrays = {}
        for name, shape in self._inputs.items():
            if name not in feeds:
                raise RleError(f"{self.path}: input '{name}' not given", code="policy.bad_input")
            arr = np.asarray(feeds[name], dtype=self._dtypes[name])
            if not _compatible(arr.shape, shape):
                raise RleError(
                    f"{self.path}: input '{name}' has shape {_fmt(arr.shape)}; declared {_fmt(shape)}",
                    code="policy.bad_input",
                )
            arrays[name] = arr
        _, ort = _import()
        options = ort.RunOptions()
        options.log_severity_level = 4
        expired = threading.Event()

        def stop() -> None:
            expired.set()
            options.terminate = True

        timer = threading.Timer(self.signature.timeout_s, stop)
        timer.start()
        try:
            values = self._session.run(self._order, arrays, options)
        except Exception as exc:  # noqa: BLE001 - onnxruntime raises its own types for model faults
            if expired.is_set():
                raise PolicyFault(
                    "onnx.timeout",
                    f"{self.path}: no result within {self.signature.timeout_s:g} s",
                    path=self.path,
                ) from None
            raise PolicyFault(
                "onnx.run", f"{self.path}: inference failed: {excerpt(exc)}", path=self.path
            ) from None
        finally:
            timer.cancel()
        out = {}
        for name, value in zip(self._order, values):
            value = np.asarray(value, dtype=np.float64)
            if not _compatible(value.shape, self._outputs[name]):
                raise PolicyFault(
                    "onnx.shape",
                    f"{self.path}: output '{name}' has shape {_fmt(value.shape)}; "
                    f"expected {_fmt(self._outputs[name])}",
                    path=self.path,
                )
            bad = int(value.size - np.count_nonzero(np.isfinite(value)))
            if bad:
                raise PolicyFault(
                    "onnx.nonfinite",
                    f"{self.path}: output '{name}' holds {bad} non-finite value(s) (NaN or inf)",
                    path=self.path,
                )
            out[name] = value
        return out


def load_onnx_policy(
    path: Path | str,
    root: Path | str,
    signature: OnnxSignature,
    dims: Mapping[str, int] = {},  # noqa: B006 - read only
) -> OnnxPolicy:
    """Load the submitted ONNX file ``path`` (relative to ``root``, the submission directory).

    Raises:
        PolicyFault: ``onnx.path``, ``onnx.size``, ``onnx.external_data``, ``onnx.load``,
            ``onnx.signature`` or ``onnx.shape``; the message names the file and the alternatives.
        RleError: ``onnx.missing_dependency`` without onnx/onnxruntime (with the install hint);
            ``policy.dims`` for a symbol without a value.
    """
    onnx, ort = _import()
    data, rel = _read(Path(path), Path(root), signature.max_bytes)
    try:
        model = onnx.load_model_from_string(data)
    except Exception as exc:  # noqa: BLE001 - protobuf decode errors
        raise PolicyFault("onnx.load", f"{rel}: not a valid ONNX model: {excerpt(exc)}", path=rel) from None
    if any(t.data_location == onnx.TensorProto.EXTERNAL or len(t.external_data) for t in _tensors(model)):
        raise PolicyFault(
            "onnx.external_data", f"{rel}: references external data files; embed every tensor", path=rel
        )
    try:
        onnx.checker.check_model(model)
    except Exception as exc:  # noqa: BLE001 - onnx raises checker and protobuf errors alike
        raise PolicyFault("onnx.load", f"{rel}: not a valid ONNX model: {excerpt(exc)}", path=rel) from None
    options = ort.SessionOptions()
    options.intra_op_num_threads = 1
    options.inter_op_num_threads = 1
    options.execution_mode = ort.ExecutionMode.ORT_SEQUENTIAL
    options.log_severity_level = 4
    try:
        session = ort.InferenceSession(data, options, providers=["CPUExecutionProvider"])
    except Exception as exc:  # noqa: BLE001 - onnxruntime raises its own types
        raise PolicyFault(
            "onnx.load", f"{rel}: onnxruntime cannot load it: {excerpt(exc)}", path=rel
        ) from None
    for kind, got, declared in (
        ("input", session.get_inputs(), signature.inputs),
        ("output", session.get_outputs(), signature.outputs),
    ):
        have = {t.name: t for t in got}
        want = [s.name for s in declared]
        # every input must be fed, so the inputs match exactly; extra outputs are not read
        if (set(have) != set(want)) if kind == "input" else not set(want) <= set(have):
            raise PolicyFault(
                "onnx.signature",
                f"{rel}: {kind} names {sorted(have)}; expected {sorted(want)}",
                path=rel,
            )
        for spec in declared:
            t = have[spec.name]
            if t.type not in _DTYPES:
                raise PolicyFault(
                    "onnx.signature",
                    f"{rel}: {kind} '{spec.name}' has type {t.type}; expected one of {', '.join(_DTYPES)}",
                    path=rel,
                )
            expected = _resolve(spec, dims)
            if not _compatible(t.shape, expected):
                raise PolicyFault(
                    "onnx.shape",
                    f"{rel}: {kind} '{spec.name}' has shape {_fmt(t.shape)}; expected {_fmt(expected)}",
                    path=rel,
                )
    return OnnxPolicy(session, signature, dims, rel)
