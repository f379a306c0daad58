"""JSON a user wrote, read with json's refusals as one clear line each."""

from __future__ import annotations

import json
import sys
from typing import Any

from tvl_cli.core.errors import BadInput


def loads(text: str, where: str, what: str, **options: Any) -> Any:
    """json.loads; its refusals beyond a syntax error (which stays json.JSONDecodeError, for
    the caller to place) as BadInput naming `where` and `what` the text was to be."""
    try:
        return json.loads(text, **options)
    except json.JSONDecodeError:
        raise
    except RecursionError:
        raise BadInput(f"{where}: JSON nested too deeply for {what}") from None
    except ValueError:  # the one other refusal of json: int() of too many digits
        limit = sys.get_int_max_str_digits()
        raise BadInput(f"{where}: a whole number of more than {limit} digits") from None
