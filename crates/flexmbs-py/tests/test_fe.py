"""FE bodies from Python: modal analysis against Euler-Bernoulli beam theory, reduction to a body
file and reading it back."""

from __future__ import annotations

import math
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

import flexmbs
from conftest import ROOT

DIRECTIONS = {"ux", "uy", "uz", "rx", "ry", "rz"}


def cantilever() -> dict:
    """examples/mbs/parts/cantilever_beam.toml as data: steel 1 m x 20 mm x 20 mm, 20 beams."""
    return {
        "body": {
            "name": "cantilever",
            "mesh": {
                "type": "beam",
                "start": [0.0, 0.0, 0.0],
                "end": [1.0, 0.0, 0.0],
                "elements": 20,
                "section": {"shape": "rectangle", "width": 0.02, "height": 0.02},
                "material": {"e": 210e9, "nu": 0.3, "rho": 7850.0},
            },
            "boundary": {"fixed": [{"nearest": [0.0, 0.0, 0.0]}]},
            "reduction": {"method": "modal", "modes": 8},
        }
    }


def first_bending_hz() -> float:
    """Euler-Bernoulli cantilever: f1 = (1.8751^2 / 2 pi) sqrt(E I / (rho A L^4))."""
    e, rho, b, length = 210e9, 7850.0, 0.02, 1.0
    i, a = b**4 / 12.0, b * b
    return 1.87510407**2 / (2 * math.pi) * math.sqrt(e * i / (rho * a * length**4))


def test_modal_matches_beam_theory() -> None:
    m = flexmbs.modal(cantilever())
    f = m["frequencies_hz"]
    assert f.shape == (8,) and m["n_rigid"] == 0
    assert m["nodes"].shape == (21, 3) and m["modes"].shape == (8, 21, 3)
    assert m["effective_mass_fraction"].shape == (8, 3)
    # labels: a numpy array of str, one dominant direction per mode
    labels = m["labels"]
    assert isinstance(labels, np.ndarray) and labels.shape == (8,) and labels.dtype == object
    assert all(isinstance(x, str) for x in labels) and set(labels) <= DIRECTIONS
    assert set(labels[:2]) == {"uy", "uz"}  # the two first bending modes
    # square section: two equal first bending modes, within 0.5 % of beam theory (20 elements)
    assert f[0] == pytest.approx(first_bending_hz(), rel=5e-3)
    assert f[1] == pytest.approx(f[0], rel=1e-9)
    assert m["omega2"][0] == pytest.approx((2 * math.pi * f[0]) ** 2, rel=1e-12)
    # the clamped node does not move
    assert np.max(np.abs(m["modes"][:, 0, :])) == 0.0
    assert flexmbs.modal(cantilever(), modes=3)["frequencies_hz"].shape == (3,)


def test_reduce_writes_a_body_file_that_reads_back(tmp_path: Path) -> None:
    out = tmp_path / "cantilever.fmb.h5"
    info = flexmbs.reduce(cantilever(), out)
    assert out.exists() and info["nodes"] == 21 and info["modes"] == 8
    body = flexmbs.read_body(out)
    ref = flexmbs.modal(cantilever())
    assert body["nodes"].shape == (21, 3) and body["modes"].shape == (8, 21, 3)
    assert np.allclose(body["frequencies_hz"], ref["frequencies_hz"], rtol=1e-9)
    assert isinstance(body["labels"], np.ndarray) and body["labels"].dtype == object
    assert list(body["labels"]) == list(ref["labels"])
    # mass-normalised modal basis: M_red = I, K_red = diag(omega^2)
    assert np.allclose(body["m_red"], np.eye(8), atol=1e-9)
    assert np.allclose(body["k_red"], np.diag(ref["omega2"]), rtol=1e-8, atol=1e-6 * ref["omega2"].max())
    with pytest.raises(flexmbs.IoError) as e:
        flexmbs.read_body(tmp_path / "missing.fmb.h5")
    assert e.value.path == str(tmp_path / "missing.fmb.h5")


def test_bad_fe_body_names_the_key() -> None:
    data = cantilever()
    data["body"]["mesh"]["elements"] = 0
    with pytest.raises(flexmbs.ModelError) as e:
        flexmbs.modal(data)
    assert e.value.key_path == "body.mesh.elements"
    data = cantilever()
    data["body"]["reduction"]["modes"] = 500
    with pytest.raises(flexmbs.ModelError) as e:
        flexmbs.modal(data)
    assert e.value.key_path == "body.reduction.modes"


def arm_link(interface: bool = True) -> dict:
    """examples/mbs/parts/arm_link.toml as data: aluminium 1 m x 20 mm x 5 mm, 40 beams, clamped
    at the start; Craig-Bampton with the end node as interface and 4 fixed-interface modes."""
    reduction = {"method": "craig-bampton", "interface": ["end"], "modes": 4} if interface else {"modes": 10}
    return {
        "body": {
            "name": "arm_link",
            "units": "SI",
            "mesh": {
                "type": "beam",
                "start": [0.0, 0.0, 0.0],
                "end": ["1 m", 0.0, 0.0],
                "elements": 40,
                "section": {"shape": "rectangle", "width": "20 mm", "height": "5 mm"},
                "material": {"e": "70 GPa", "nu": 0.33, "rho": "2700 kg/m^3"},
            },
            "boundary": {"fixed": ["start"]},
            "reduction": reduction,
        }
    }


def test_craig_bampton_reduction_from_python_data(tmp_path: Path) -> None:
    """The basis is the 6 static constraint modes of the interface node (a beam node: 6 free DOFs)
    and the 4 fixed-interface modes; the reduced model's frequencies are Rayleigh-Ritz upper
    bounds of the full model's, close to them for the lowest modes."""
    out = tmp_path / "arm_link.fmb.h5"
    info = flexmbs.reduce(arm_link(), out)
    assert info["nodes"] == 41 and info["modes"] == 6 * 1 + 4
    body = flexmbs.read_body(out)
    assert "CraigBampton" in body["kind"]
    end = body["interface_nodes"]
    assert len(end) == 1 and np.array_equal(body["nodes"][end[0]], [1.0, 0.0, 0.0])
    assert np.array_equal(body["nodes"][body["fixed_nodes"]], [[0.0, 0.0, 0.0]])
    assert body["modes"].shape == (10, 41, 3) and body["rotations"].shape == (10, 41, 3)
    assert body["k_red"].shape == body["m_red"].shape == (10, 10)
    # constraint mode j: unit displacement (j < 3) or rotation (j >= 3) of the interface node in
    # direction j, nothing else there; the fixed-interface modes leave the interface node at rest
    at_end = np.concatenate([body["modes"][:, end[0], :], body["rotations"][:, end[0], :]], axis=1)
    assert np.array_equal(at_end[:6], np.eye(6))
    assert np.array_equal(at_end[6:], np.zeros((4, 6)))
    node_id = body["node_ids"][end[0]]
    names = ["ux", "uy", "uz", "rx", "ry", "rz"]
    assert list(body["labels"][:6]) == [f"static node {node_id} {d}" for d in names]
    assert set(body["labels"][6:]) <= DIRECTIONS
    # the reduced model (interface free) against the full model's lowest modes
    full = flexmbs.modal(arm_link(interface=False), modes=10)["frequencies_hz"]
    reduced = body["frequencies_hz"]
    assert reduced.shape == (10,) and np.all(np.diff(reduced) >= 0.0)
    assert np.all(reduced >= full * (1.0 - 1e-9)), (reduced, full)
    # 4 fixed-interface modes + the tip's static response: the 6 lowest within 0.5 % (measured:
    # 3e-4 for the 3 lowest, 1.5e-3 to 4e-3 for modes 4 to 6)
    assert np.allclose(reduced[:3], full[:3], rtol=5e-4, atol=0.0), (reduced, full)
    assert np.allclose(reduced[:6], full[:6], rtol=5e-3, atol=0.0), (reduced, full)


def _ccx_or_skip() -> None:
    """ccx as the Rust tests find it ($FLEXMBS_CCX, else PATH); missing: skip, or fail with
    FLEXMBS_REQUIRE_TOOLS=1 (CI)."""
    env = os.environ.get("FLEXMBS_CCX")
    if (env and os.access(env, os.X_OK)) or shutil.which("ccx"):
        return
    reason = "ccx (CalculiX) not found in PATH or $FLEXMBS_CCX (apt-get install calculix-ccx)"
    if os.environ.get("FLEXMBS_REQUIRE_TOOLS") == "1":
        pytest.fail(reason + " (FLEXMBS_REQUIRE_TOOLS=1: a missing tool fails the test)")
    pytest.skip(reason)


# CalculiX's own frequencies of the deck (examples/calculix/beam_freq.inp; the recipe's values,
# crates/flexmbs-validate/tests/calculix_beam.rs)
CCX_HZ = [16.73174, 16.73174, 104.6634, 104.6634, 292.1994, 292.1994]


def test_calculix_deck_as_body_source(tmp_path: Path) -> None:
    """examples/calculix_beam.toml as Python data: the C3D20R deck's K and M assembled by CalculiX
    (ccx) give CalculiX's frequencies; the same body as from the file, bit for bit."""
    _ccx_or_skip()
    data = {
        "body": {
            "name": "calculix_beam",
            "mesh": {"type": "calculix", "deck": "calculix/beam_mat.inp", "matrices": "ccx"},
            "reduction": {"modes": 6, "mass": "consistent"},
        }
    }
    model = flexmbs.Model.from_dict(data, base_dir=ROOT / "examples")  # the deck's path is relative
    m = flexmbs.modal(model)
    assert m["independent_dofs"] == 3600 and m["n_rigid"] == 0
    # the .dat table prints 7 significant digits: 1e-6 relative is its resolution
    assert np.allclose(m["frequencies_hz"], CCX_HZ, rtol=1e-6, atol=0.0), m["frequencies_hz"]
    from_file = flexmbs.modal(ROOT / "examples" / "calculix_beam.toml")
    assert np.array_equal(m["frequencies_hz"], from_file["frequencies_hz"])
    # reduced and read back: the deck's nodes, clamped at x = 0
    out = tmp_path / "calculix_beam.fmb.h5"
    info = flexmbs.reduce(model, out)
    body = flexmbs.read_body(out)
    assert info["modes"] == 6 and body["nodes"].shape == m["nodes"].shape
    assert np.allclose(body["frequencies_hz"], m["frequencies_hz"], rtol=1e-9)
    fixed = body["nodes"][body["fixed_nodes"]]
    assert len(fixed) > 0 and np.all(fixed[:, 0] == 0.0)
    # a deck that is not there names the key
    data["body"]["mesh"]["deck"] = "calculix/missing.inp"
    with pytest.raises(flexmbs.Error) as e:
        flexmbs.modal(flexmbs.Model.from_dict(data, base_dir=ROOT / "examples"))
    assert "missing.inp" in str(e.value)
