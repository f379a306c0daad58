"""One module per verb: files in, a typed result out; what the `tvl` commands call."""

__all__ = [
    "baseline",
    "contact_autopsy",
    "demo",
    "design",
    "diff",
    "explain",
    "export",
    "figure",
    "inspect",
    "learn",
    "replay",
    "run",
    "train",
    "world",
    "world_export",
    "world_import",
]
