"""The algorithms a server offers and the parameters each declares (GetServerInfo), and how a
parameter's value travels in a JobSpec. The declarations live in the server's core (one per
parameter, beside the settings it fills); this module only reads them."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Tuple

from ._stubs import pb2

_BUDGET_NAMES = {
    pb2.BUDGET_KIND_SAMPLES_PER_PIXEL: "spp",
    pb2.BUDGET_KIND_MUTATIONS_PER_PIXEL: "mpp",
    pb2.BUDGET_KIND_SECONDS: "seconds",
}


def value_from_proto(v: "pb2.ParameterValue") -> Any:
    which = v.WhichOneof("value")
    if which is None:
        return None
    if which == "rgb_value":
        return (v.rgb_value.r, v.rgb_value.g, v.rgb_value.b)
    return getattr(v, which)


def value_to_proto(value: Any, out: "pb2.ParameterValue") -> None:
    """bool, int, float, str or an (R, G, B) triple into a ParameterValue; the server converts
    it to the parameter's declared type where that is exact, and refuses it otherwise."""
    if isinstance(value, bool):
        out.bool_value = value
    elif isinstance(value, int):
        if value >= 2 ** 63:
            out.uint_value = value
        else:
            out.int_value = value
    elif isinstance(value, float):
        out.real_value = value
    elif isinstance(value, str):
        out.text_value = value
    elif isinstance(value, (tuple, list)) and len(value) == 3:
        out.rgb_value.r, out.rgb_value.g, out.rgb_value.b = (float(c) for c in value)
    else:
        try:  # numpy scalars and the like
            value_to_proto(value.item(), out)
        except AttributeError:
            raise ValueError(f"a parameter value must be a bool, number, text or (R, G, B), "
                             f"got {value!r}") from None


@dataclass
class Parameter:
    """One declared parameter: its name (the keyword of submit(); '-' may stand for '_'),
    type ("bool", "int", "uint", "real", "text", "choice", "rgb"), default (None: off unless
    given), range, choices, unit and one line of help; shared: every algorithm takes it."""
    name: str
    type: str
    help: str = ""
    unit: str = ""
    default: Any = None
    min: Optional[float] = None
    max: Optional[float] = None
    min_exclusive: bool = False
    choices: Tuple[str, ...] = ()
    shared: bool = False

    @classmethod
    def from_proto(cls, p: "pb2.ParameterInfo") -> "Parameter":
        return cls(p.name, p.type, p.help, p.unit,
                   value_from_proto(p.default_value) if p.HasField("default_value") else None,
                   p.min if p.HasField("min") else None, p.max if p.HasField("max") else None,
                   p.min_exclusive, tuple(p.choices), p.shared)


@dataclass
class Algorithm:
    """An algorithm of the server: its name, description, budgets ("spp" or "mpp", and
    "seconds") and its parameters by name (the shared ones first)."""
    name: str
    description: str
    budgets: Tuple[str, ...]
    parameters: Dict[str, Parameter] = field(default_factory=dict)

    @classmethod
    def from_proto(cls, a: "pb2.AlgorithmInfo") -> "Algorithm":
        native = _BUDGET_NAMES.get(a.native_budget, "")
        budgets = tuple(b for b in (native, "seconds") if b)
        return cls(a.name, a.description, budgets,
                   {p.name: Parameter.from_proto(p) for p in a.parameter_info})

    def own_parameters(self) -> List[Parameter]:
        """Its own parameters, without the shared ones."""
        return [p for p in self.parameters.values() if not p.shared]
