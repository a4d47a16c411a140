"""Runs ``geardyn.report`` in a child process (so that the parent can stop it on Ctrl-C).

Usage: ``python -m geardyn._report_child JSON``; prints one JSON line: ``{"index": path}`` or
``{"error": exception class, "message": text}``.
"""

import json
import signal
import sys


def main():
    # the parent decides what Ctrl-C does (it ends this process)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    args = json.loads(sys.argv[1])
    from geardyn import _geardyn

    try:
        index = _geardyn.report(args["preset"], args["sets"], args["quick"], args["out"])
    except (ValueError, OSError, RuntimeError) as e:
        kind = next(k for k in (OSError, ValueError, RuntimeError) if isinstance(e, k))
        print(json.dumps({"error": kind.__name__, "message": str(e)}))
        return 1
    print(json.dumps({"index": index}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
