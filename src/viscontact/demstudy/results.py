"""What the DEM study runs (its configurations, quick and full) and what it returns, with the
names of the files its report consists of."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..physics.laws import STUDY_MODELS
from . import bounce as bounce_mod
from . import flow as flow_mod
from . import gas as gas_mod

DEFAULT_OUT = "viscontact-dem-study"
INPUTS = ("bounce.in", "gas_prepare.in", "gas_cool.in", "collapse_prepare.in", "collapse.in")
FIGURES = ("bounce.png", "bounce_series.png", "gas_cooling.png", "gas_snapshot.png",
           "collapse.png", "collapse_snapshot.png")
TABLES = ("bounce", "bounce_sequence", "gas", "flow", "flow_laws", "flow_runs")


@dataclass(frozen=True)
class StudyConfig:
    balls: tuple[str, ...]
    gas: gas_mod.GasSetup
    flow: flow_mod.FlowSetup
    haff: gas_mod.HaffCheck = gas_mod.QUICK_HAFF
    models: tuple[str, ...] = STUDY_MODELS
    quick: bool = False


QUICK = StudyConfig(balls=("ILB",), gas=gas_mod.QUICK_GAS, flow=flow_mod.QUICK_FLOW,
                    haff=gas_mod.QUICK_HAFF, quick=True)
FULL = StudyConfig(balls=("ILB", "OLB"), gas=gas_mod.FULL_GAS, flow=flow_mod.FULL_FLOW,
                   haff=gas_mod.FULL_HAFF)


def report_files(cfg: StudyConfig) -> list[str]:
    """Names of the files a report consists of (the marker excluded)."""
    files = [f"{t}.{ext}" for t in TABLES for ext in ("csv", "md")] + list(FIGURES)
    files += ["index.html", "results.json"] + list(INPUTS)
    files += [f"gas-{m}.dump" for m in cfg.models]
    files += [f"collapse-{m}-seed{cfg.flow.seeds[0]}.dump" for m in cfg.models]
    files += [f"coeffs-gas-{m}.lmp" for m in cfg.models]
    files += [f"coeffs-collapse-{m}.lmp" for m in cfg.models]
    files += [f"coeffs-bounce-{b}-{m}.lmp" for b in cfg.balls for m in cfg.models]
    return files


@dataclass
class Results:
    cfg: StudyConfig
    bounces: list[bounce_mod.BounceCase] = field(default_factory=list)
    gas: gas_mod.GasStudy | None = None
    flow: flow_mod.FlowStudy | None = None
    seconds: dict[str, float] = field(default_factory=dict)
    np_: int = 1
