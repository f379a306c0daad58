"""JSON a user wrote, read with json's refusals as one clear line each."""

from __future__ import annotations

import json
import sys
from typing import Any

from tvl_cli.core.errors import BadInput
from tvl_cli.core.nesting import check_nesting, too_deep


def loads(text: str, where: str, **options: Any) -> Any:
    """json.loads; its refusals beyond a syntax error (which stays json.JSONDecodeError, for
    the caller to place) as BadInput naming `where`, and so is a value nested deeper than
    core.nesting allows."""
    try:
        value = json.loads(text, **options)
    except json.JSONDecodeError:
        raise
    except RecursionError:
        raise too_deep(where) from None
    except ValueError:  # the one other refusal of json: int() of too many digits
        limit = sys.get_int_max_str_digits()
        raise BadInput(f"{where}: a whole number of more than {limit} digits") from None
    check_nesting(value, where)
    return value
