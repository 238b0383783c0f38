"""What the example scripts share: where pictures go and the --quick switch.

OUT (environment) is the results directory (default: results/); each script writes
OUT/python/<name>.png. --quick runs a small grid with a short protocol (the tests use it)."""
import os
import sys

QUICK = "--quick" in sys.argv[1:]
# The paper's protocol is the library's default (500 impacts discarded, 200 points kept).
PROTOCOL = dict(transient=100, record=40) if QUICK else {}


def pick(full, quick):
    return quick if QUICK else full


def picture(name):
    directory = os.path.join(os.environ.get("OUT", "results"), "python")
    os.makedirs(directory, exist_ok=True)
    return os.path.join(directory, name)
