"""The contact network in Python: FillResult.contacts / .coordination and
pfill.contacts(), against a brute-force search and the command line."""
import json
import os
import subprocess

import numpy as np
import pytest

import pfill

CLI = os.environ.get("PFILL_CLI", "pfill")


def brute_force(positions, radii, gap):
    d = np.sqrt(((positions[:, None, :] - positions[None, :, :]) ** 2).sum(-1))
    touching = d - radii[:, None] - radii[None, :] <= gap * np.minimum(radii[:, None], radii[None, :])
    i, j = np.nonzero(np.triu(touching, 1))
    return set(zip(i.tolist(), j.tolist()))


@pytest.fixture(scope="module")
def cube_fill():
    return pfill.fill("cube", count=200, seed=2)


def test_fill_result_contacts_equal_a_brute_force_search(cube_fill):
    pairs = cube_fill.contacts
    assert pairs.dtype == np.int64 and pairs.ndim == 2 and pairs.shape[1] == 2
    assert (pairs[:, 0] < pairs[:, 1]).all()
    assert set(map(tuple, pairs.tolist())) == brute_force(cube_fill.positions, cube_fill.radii, 0.02)
    c = cube_fill.coordination
    assert c.shape == (len(cube_fill),)
    assert c.sum() == 2 * len(pairs)
    assert c.mean() == pytest.approx(cube_fill.metrics["mean_coordination"], abs=0.1)


def test_contacts_with_a_gap_and_the_wall(cube_fill):
    net = pfill.contacts(cube_fill.positions, cube_fill.radii, gap=0.1, mesh="cube")
    assert set(map(tuple, net["pairs"].tolist())) == brute_force(cube_fill.positions, cube_fill.radii, 0.1)
    assert net["gaps"].shape == (len(net["pairs"]),)
    assert len(net["wall_particles"]) > 0
    # Wall contacts of the cube: the normal is an axis, the point on a face, the sphere within the gap of it.
    n = net["wall_normals"]
    assert np.allclose(np.abs(n).max(axis=1), 1)
    assert np.allclose(np.abs(net["wall_points"]).max(axis=1), 1)
    r = cube_fill.radii[net["wall_particles"]]
    assert (net["wall_gaps"] <= 0.1 * r + 1e-12).all()
    assert net["report"]["wall_contacts"] == len(net["wall_particles"])
    with pytest.raises(pfill.Error, match="contact gap"):
        pfill.contacts(cube_fill.positions, cube_fill.radii, gap=-1)


def test_the_command_line_writes_the_same_pairs(tmp_path):
    r = pfill.fill("cube", count=150, seed=4)
    subprocess.run([CLI, "fill", "cube", "-n", "150", "--seed", "4", "-q", "--contacts", "-o", str(tmp_path / "c.csv"),
                    "--pairs", str(tmp_path / "pairs.csv"), "--report", str(tmp_path / "c.json")],
                   check=True, stdout=subprocess.DEVNULL)
    report = json.loads((tmp_path / "c.json").read_text())
    assert report["contacts"]["pairs"] == len(r.contacts)
    rows = np.loadtxt(tmp_path / "pairs.csv", delimiter=",", skiprows=1)
    pair_rows = rows[rows[:, 1] > 0]
    index_of = {int(i): k for k, i in enumerate(r.ids)}
    cli_pairs = {tuple(sorted((index_of[int(a)], index_of[int(b)]))) for a, b in pair_rows[:, :2]}
    assert cli_pairs == set(map(tuple, r.contacts.tolist()))
    particles = np.loadtxt(tmp_path / "c.csv", delimiter=",", skiprows=1)
    assert particles[:, -1].sum() == 2 * len(r.contacts)  # the coordination column
