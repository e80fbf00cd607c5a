"""What a submission must expose (``Protocol`` of ``FunctionSpec``) and the limits over one runner's life
(``Budget``): the declarations a family makes and ``policy.PolicyRunner`` enforces."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from rle_design.errors import MissingElement

__all__ = ["Budget", "Dim", "FunctionSpec", "Protocol"]

Dim = int | str | None
"""One dimension of a declared shape: a size, a symbol resolved at construction, or None (any)."""


@dataclass(frozen=True)
class FunctionSpec:
    """One function a submission must expose.

    Attributes:
        name: Module-level callable name.
        args: Human description of the arguments, with units.
        returns: Shape of the returned array (symbolic entries resolved from the runner's ``dims``;
            None entries match any size); None returns anything of the wire format.
        finite: Fault on NaN or infinity anywhere in the result.
        timeout_s: Wall-clock cap of one call [s]; the runner caps it further by its hang cap.
    """

    name: str
    args: str
    returns: tuple[Dim, ...] | None = None
    finite: bool = True
    timeout_s: float = 30.0

    def __post_init__(self) -> None:
        if not self.name.isidentifier():
            raise ValueError(f"function name must be an identifier, got {self.name!r}")
        if not self.timeout_s > 0:
            raise ValueError(f"{self.name}: timeout_s must be > 0, got {self.timeout_s}")
        for d in self.returns or ():
            ok = d is None or (isinstance(d, str) and d.isidentifier()) or (isinstance(d, int) and d >= 0)
            if not ok:
                raise ValueError(f"{self.name}: dimension {d!r} is not a size, a symbol or None")

    def shape(self, dims: Mapping[str, int]) -> tuple[int | None, ...] | None:
        """The return shape with symbols replaced by ``dims``.

        Raises:
            MissingElement: ``policy.dims`` when a symbol has no value (lists the known ones).
        """
        if self.returns is None:
            return None
        out: list[int | None] = []
        for d in self.returns:
            if isinstance(d, str):
                if d not in dims:
                    raise MissingElement("dimension", d, available=dims, code="policy.dims")
                out.append(int(dims[d]))
            else:
                out.append(d)
        return tuple(out)


@dataclass(frozen=True)
class Protocol:
    """The functions a submitted module exposes.

    Attributes:
        module: Module name in the child, the prefix of every fault message (``module.fn()``).
        functions: The declared functions.
    """

    module: str
    functions: tuple[FunctionSpec, ...]

    def __post_init__(self) -> None:
        if not self.module.isidentifier():
            raise ValueError(f"protocol module name must be an identifier, got {self.module!r}")
        names = [f.name for f in self.functions]
        if len(set(names)) != len(names):
            raise ValueError(f"protocol '{self.module}' declares a function twice: {names}")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f.name for f in self.functions)

    def function(self, name: str) -> FunctionSpec:
        """The declaration of ``name``.

        Raises:
            MissingElement: ``policy.undeclared`` (a verifier bug: it calls what it never declared).
        """
        for f in self.functions:
            if f.name == name:
                return f
        raise MissingElement("function", name, available=self.names, code="policy.undeclared")


@dataclass(frozen=True)
class Budget:
    """Limits over one runner's whole life (all its children).

    Attributes:
        max_faults: Faults after which calls are refused (``policy.fault_budget``); None: no limit.
        cpu_s: CPU time of all children together [s].
        restart: Start a fresh child on the call after a fault; False keeps one child for the run.
    """

    max_faults: int | None = 3
    cpu_s: float = 600.0
    restart: bool = True

    def __post_init__(self) -> None:
        if self.max_faults is not None and self.max_faults < 1:
            raise ValueError(f"Budget.max_faults must be >= 1 or None, got {self.max_faults}")
        if not self.cpu_s > 0:
            raise ValueError(f"Budget.cpu_s must be > 0, got {self.cpu_s}")
