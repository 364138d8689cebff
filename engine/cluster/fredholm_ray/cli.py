"""The fredholm-ray console script: parse, render, and turn every failure into one line and an exit status."""
import sys

import ray

from .driver import RenderFailed, run_render
from .options import parse_render_request
from .plan import UsageError


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    try:
        run_render(parse_render_request(argv))
    except UsageError as e:
        print(f"fredholm-ray: {e}", file=sys.stderr)
        return 2
    except RenderFailed as e:
        print(f"fredholm-ray: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("fredholm-ray: interrupted", file=sys.stderr)
        return 130
    finally:
        if ray.is_initialized():
            ray.shutdown()
    return 0
