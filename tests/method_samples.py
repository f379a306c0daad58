"""Methods the tests give the FAMs they make by hand."""

from __future__ import annotations

from dataclasses import replace

from tvl_cli.core.memory import NO_MEMORY
from tvl_cli.core.method import DEFAULT

# Ours, reading the live ring: what a hand-made FAM's runs read, free of any echo memory.
LIVE_RING = replace(DEFAULT, memory=NO_MEMORY)
