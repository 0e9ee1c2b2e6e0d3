"""The hunt-and-fill search on deciders whose collapsing set is known exactly.

Each decider collapses on a union of intervals of factors; the claims of the search (the first
collapse found, ``smallest`` only when the scan below it reached the resolution, the safe factors
above it, the resolution reached) are checked against that set.
"""
import math

import pytest

from fembeam.errors import InputError
from fembeam.studies.huntfill import HUNT_STEP, hunt_and_fill

ONSET = 0.7


def decider(windows, log=None):
    """Collapses on the closed intervals ``windows``; records every factor asked."""
    def run(f):
        if log is not None:
            log.append(f)
        return {"outcome": "overturned" if any(a <= f <= b for a, b in windows) else "rest"}
    return run


def check_claims(res, windows, resolution):
    """What ``smallest`` promises: every gap from the onset to the first collapse at most
    1 + resolution, all safe below; the outcomes those of the decider; the safe ones above listed."""
    runs = res["scan"]
    assert res["runs"] == len(runs) and "converged" not in res
    assert res["first_overturning"] == res["first_collapse"]          # the deprecated alias
    assert res["safe_above"] == bool(res["safe_factors_above"])
    assert [r["factor"] for r in runs] == sorted(r["factor"] for r in runs)
    for r in runs:
        assert r["outcome"] == ("overturned" if any(a <= r["factor"] <= b for a, b in windows) else "rest")
        assert r["factor"] > ONSET
    first = res["first_collapse"]
    below = [ONSET] + [r["factor"] for r in runs if first is None or r["factor"] < first] + \
        ([first] if first is not None else [])
    assert all(r["outcome"] == "rest" for r in runs if first is None or r["factor"] < first)
    widest = max(b / a - 1 for a, b in zip(below, below[1:]))
    assert res["resolution_reached"] == pytest.approx(widest, rel=1e-12)
    if res["smallest"]:
        assert widest <= resolution * (1 + 1e-9)
    if first is not None:
        above = [r["factor"] for r in runs if r["factor"] > first and r["outcome"] == "rest"]
        assert res["safe_factors_above"] == above
        assert res["bracket"][1] == first and res["bracket"][0] == below[-2]


def test_threshold_is_bracketed_to_the_resolution():
    log = []
    res = hunt_and_fill(decider([(1.3, math.inf)], log), ONSET, resolution=0.01, max_factor=20 * ONSET)
    check_claims(res, [(1.3, math.inf)], 0.01)
    lo, hi = res["bracket"]
    assert res["smallest"] and 1.3 <= hi <= 1.3 * 1.01 and lo < 1.3 and hi / lo <= 1.01 * (1 + 1e-9)
    # the hunt: steps of 10 %, 20 %, 30 % ... from the onset until the first collapse
    f, hunt = ONSET, []
    while f < 1.3:
        f *= 1 + (len(hunt) + 1) * HUNT_STEP
        hunt.append(f)
    assert log[:len(hunt)] == pytest.approx(hunt, rel=1e-15)
    # the fill costs ceil(log ratio / log 1.01) - 1 runs per hunt gap: no more than a uniform scan
    ends = [ONSET] + hunt
    need = sum(math.ceil(math.log(b / a) / math.log1p(0.01) - 1e-12) - 1 for a, b in zip(ends, ends[1:]))
    assert res["runs"] <= len(hunt) + need + 1
    assert res["runs"] <= math.log(hi / ONSET) / math.log1p(0.01) + len(hunt) + 2


def test_a_window_below_the_hunts_collapse_is_found_and_the_collapse_above_reported():
    windows = [(1.0, 1.03), (1.5, math.inf)]     # 3 % wide, between the hunt's runs at 0.924 and 1.2012
    res = hunt_and_fill(decider(windows), ONSET, resolution=0.02, max_factor=20 * ONSET)
    check_claims(res, windows, 0.02)
    assert res["smallest"] and 1.0 <= res["first_collapse"] <= 1.03
    assert 1.2012 in [round(f, 6) for f in res["safe_factors_above"]]
    assert all(1.03 < f < 1.5 for f in res["safe_factors_above"])


def test_a_window_narrower_than_the_resolution_may_be_missed_but_then_nothing_is_overstated():
    windows = [(0.841, 0.843), (1.03, math.inf)]             # a block under El Centro has such windows
    coarse = hunt_and_fill(decider(windows), ONSET, resolution=0.05, max_factor=20 * ONSET)
    fine = hunt_and_fill(decider(windows), ONSET, resolution=0.002, max_factor=20 * ONSET)
    for res, resolution in ((coarse, 0.05), (fine, 0.002)):
        check_claims(res, windows, resolution)
        assert res["smallest"]
    assert coarse["first_collapse"] >= 1.03                # the 0.24 % window lies between two runs
    assert 0.841 <= fine["first_collapse"] <= 0.843        # 0.2 % steps cannot jump over it


def test_budget_stops_the_search_without_claiming_the_smallest():
    res = hunt_and_fill(decider([(3.0, math.inf)]), ONSET, resolution=0.01, max_factor=20 * ONSET, max_runs=12)
    check_claims(res, [(3.0, math.inf)], 0.01)
    assert res["runs"] == 12 and res["budget_exhausted"] and not res["smallest"]
    assert res["first_collapse"] is not None and res["resolution_reached"] > 0.01


def test_no_collapse_up_to_the_largest_factor():
    res = hunt_and_fill(decider([]), ONSET, resolution=0.05, max_factor=10 * ONSET)
    check_claims(res, [], 0.05)
    assert res["first_collapse"] is None and res["none_up_to_max"] and not res["smallest"]
    assert res["scan"][-1]["factor"] == 10 * ONSET and res["bracket"] == [10 * ONSET, None]


def test_a_failed_run_stops_the_search():
    def run(f):
        if f > 1.2:
            return {"outcome": "solver_error", "error": "SolverError: no"}
        return {"outcome": "rest"}
    res = hunt_and_fill(run, ONSET, resolution=0.05, max_factor=20 * ONSET)
    assert res["first_collapse"] is None and not res["smallest"] and not res["none_up_to_max"]
    assert len(res["errors"]) == 1 and res["errors"][0]["factor"] > 1.2
    assert res["errors"][0]["error"] == res["scan"][-1]["error"] == "SolverError: no"


@pytest.mark.parametrize("kw", [dict(resolution=0.0), dict(resolution=2.0), dict(max_factor=math.nan),
                                dict(max_runs=0), dict(max_runs=1.5)])
def test_bad_settings(kw):
    args = dict(resolution=0.05, max_factor=10.0, max_runs=10) | kw
    with pytest.raises(InputError):
        hunt_and_fill(decider([]), ONSET, **args)


# --------------------------------------------------------------------------- onset_safe=False
WINDOW_AND_ABOVE = [(1.0, 1.03), (1.5, math.inf)]      # a 3 % window, then collapse from 1.5 up


def test_onset_not_safe_runs_the_onset_and_never_claims_the_smallest():
    """Joints that may slide below A_L: the onset factor is run (first), the rest of the search is
    the one of a safe onset, and the collapse found is not called the smallest although the
    gaps below it reached the resolution."""
    log = []
    res = hunt_and_fill(decider(WINDOW_AND_ABOVE, log), ONSET, resolution=0.02, max_factor=20 * ONSET,
                        onset_safe=False)
    safe = hunt_and_fill(decider(WINDOW_AND_ABOVE), ONSET, resolution=0.02, max_factor=20 * ONSET)
    assert log[0] == ONSET and res["scan"][0]["factor"] == ONSET and res["scan"][0]["order"] == 0
    assert res["scan"][0]["outcome"] == "rest"
    # the same runs as with a safe onset, plus the onset's
    assert [r["factor"] for r in res["scan"]] == [ONSET] + [r["factor"] for r in safe["scan"]]
    first = res["first_collapse"]
    assert first == safe["first_collapse"] and 1.0 <= first <= 1.03
    assert not res["smallest"] and safe["smallest"]
    # the claims against the known set, by hand: every run below the first collapse is safe and
    # the widest ratio between consecutive factors run from the onset up to it is the one reported
    below = sorted(f for f in log if f <= first)
    assert all(not 1.0 <= f <= 1.03 for f in below[:-1])
    widest = max(b / a - 1 for a, b in zip(below, below[1:]))
    assert res["resolution_reached"] == pytest.approx(widest, rel=1e-12) and widest <= 0.02 * (1 + 1e-9)
    assert res["bracket"] == [below[-2], first]
    # safe factors above: every run above the first collapse outside the collapsing set, in order
    above = sorted(f for f in log if f > first and not (1.0 <= f <= 1.03 or f >= 1.5))
    assert res["safe_factors_above"] == above and res["safe_above"]
    assert any(1.03 < f < 1.5 for f in above) and all(1.03 < f < 1.5 for f in above)
    assert not res["none_up_to_max"] and not res["budget_exhausted"] and res["errors"] == []


def test_onset_not_safe_and_collapsing_is_one_run():
    """A collapse at the onset factor ends the search: one run, no safe factor seen (the bracket's
    lower end unknown), nothing above it searched."""
    log = []
    res = hunt_and_fill(decider([(0.5, 0.75), (1.5, math.inf)], log), ONSET, resolution=0.02,
                        max_factor=20 * ONSET, onset_safe=False)
    assert log == [ONSET] and res["runs"] == 1
    assert res["first_collapse"] == ONSET and res["collapse"] == "overturned"
    assert not res["smallest"] and res["safe_factors_above"] == [] and not res["safe_above"]
    assert res["resolution_reached"] == 0.0 and res["bracket"] == [None, ONSET]


def test_onset_not_safe_without_collapse_claims_nothing_up_to_the_largest_factor():
    res = hunt_and_fill(decider([(0.1, 0.2)]), ONSET, resolution=0.05, max_factor=10 * ONSET, onset_safe=False)
    assert res["first_collapse"] is None and not res["smallest"]
    assert not res["none_up_to_max"]          # below the onset is not searched
    assert res["scan"][0]["factor"] == ONSET and res["scan"][-1]["factor"] == 10 * ONSET
    assert res["resolution_reached"] <= 0.05 * (1 + 1e-9) and res["bracket"] == [10 * ONSET, None]
