"""simulate(): the values of `geartopo simulate`'s files to the last printed digit, the arrays' types and shapes,
progress, and the GIL released while it works."""
import threading
import time

import numpy as np
import pytest

import geartopo
from conftest import SCENE, file_lines, run_cli, topology_lines, traces_lines


@pytest.mark.parametrize("method", ["exact", "linear"])
def test_simulate_equals_the_cli_files(scene, tmp_path, method):
    run_cli("simulate", SCENE, "--out", tmp_path, "--teeth", "1,18", "--method", method)
    topo = geartopo.simulate(scene, teeth=[1, 18], method=method)
    assert topology_lines(topo) == file_lines(tmp_path / "topology.csv")
    assert traces_lines(topo["traces"]) == file_lines(tmp_path / "traces.csv")


def test_dense_grid_equals_dense_csv(scene, tmp_path):
    run_cli("simulate", SCENE, "--out", tmp_path, "--teeth", "5", "--dense", "6x11")
    topo = geartopo.simulate(scene, teeth=[5], dense=(6, 11))
    assert len(topo["dense"]["tooth"]) == 2 * 6 * 11
    assert topology_lines(topo["dense"]) == file_lines(tmp_path / "dense.csv")


def test_arrays_types_and_shapes(scene):
    topo = geartopo.simulate(scene, teeth=[1, 18])
    n = 2 * 2 * 7 * 9  # teeth × flanks × the scene's 7 × 9 grid
    for key in ("tooth", "row", "col"):
        assert topo[key].dtype == np.int32 and topo[key].shape == (n,)
    for key in ("diameter_mm", "z_mm", "deviation_um", "design_um", "roll_length_mm"):
        assert topo[key].dtype == np.float64 and topo[key].shape == (n,)
    assert topo["flank"].dtype == np.dtype("<U5") and set(topo["flank"]) == {"left", "right"}
    # Filled in place: each array's memory is its own block (its base the module's capsule, not another array),
    # contiguous and writable; nothing copied on the way to numpy.
    for key in ("tooth", "flank", "deviation_um"):
        a = topo[key]
        assert a.flags.c_contiguous and a.flags.writeable and not isinstance(a.base, np.ndarray)
    traces = topo["traces"]
    assert traces["trace"].dtype == np.dtype("<U7")
    assert len(traces["tooth"]) == 2 * 2 * (100 + 150)  # profile_points + helix_points per flank
    assert (traces["trace"] == "profile").sum() == 2 * 2 * 100
    assert "dense" not in topo and topo["method"] == "exact" and (topo["rows"], topo["cols"]) == (7, 9)


def test_teeth_all_and_the_scene_default(scene):
    assert set(geartopo.simulate(scene, teeth="all", method="linear")["tooth"]) == set(range(1, 36))
    assert set(geartopo.simulate(scene, method="linear")["tooth"]) == set(range(1, 36))  # the scene lists none


def test_progress_reports_every_flank(scene):
    reports = []
    geartopo.simulate(scene, teeth=[1, 2, 3], method="linear", progress=lambda done, total: reports.append((done, total)))
    assert reports[-1] == (6, 6)
    assert [d for d, _ in reports] == sorted(d for d, _ in reports)


def test_an_exception_in_progress_stops_the_work(scene):
    def stop(done, total):
        raise KeyboardInterrupt("stop")

    with pytest.raises(KeyboardInterrupt, match="stop"):
        geartopo.simulate(scene, teeth=[1, 2, 3, 4], progress=stop, threads=1)


def test_the_gil_is_released_while_simulating(scene):
    """Another Python thread runs while simulate works: its counter moves on during the call."""
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    time.sleep(0.01)
    start = time.perf_counter()
    geartopo.simulate(scene, teeth="all", method="exact", dense=(50, 100))  # a few tenths of a second
    end = time.perf_counter()
    stop.set()
    t.join()
    assert end - start > 0.05, "the call should take long enough to tell"
    assert sum(start < x < end for x in ticks) >= 10


def test_results_never_share_memory(scene):
    """The columns' blocks are reused once Python frees them (column_memory.hpp), never while a result lives."""
    first = geartopo.simulate(scene, teeth=[1, 18], method="linear")
    kept = {k: first[k].copy() for k in ("tooth", "flank", "deviation_um")}
    for _ in range(3):
        again = geartopo.simulate(scene, teeth=[1, 18], method="exact")
        for k in kept:
            assert not np.shares_memory(first[k], again[k])
        again["deviation_um"][:] = 1e6  # scribbling on a later result leaves the first alone
        del again
    for k in kept:
        np.testing.assert_array_equal(first[k], kept[k])
