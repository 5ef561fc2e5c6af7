"""What the study table scripts (partitioned-study-table.py, guided-study-table.py) share: the
shipped scenes, reading `partita-eval quality` JSON files and picking their figures, and the
number formats of the studies' tables in docs/."""
import json

SCENES = ["cornell", "cornell-glass", "cornell-point", "door-ajar", "bathroom", "pool"]


def g(x, digits=3):
    return "-" if x is None else f"{x:.{digits}g}"


def pm(mean, std, digits=3):
    return f"{g(mean, digits)} +- {g(std, 2)}"


def load(path):
    """A JSON file, or None when it does not exist (a scene or run the study skipped)."""
    try:
        with open(path) as f:
            return json.load(f)
    except FileNotFoundError:
        return None


def result(j, algorithm, index=0):
    """The index-th result of `algorithm` in a quality JSON, or None."""
    found = [r for r in j["results"] if r["algorithm"] == algorithm]
    return found[index] if len(found) > index else None


def stat_mean(r, key):
    return r["statistics_mean"].get(key)


def units(r):
    return int(r["units_per_pixel_mean"] + 0.5)
