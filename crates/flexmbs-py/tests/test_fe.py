"""FE bodies from Python: modal analysis against Euler-Bernoulli beam theory, reduction to a body
file and reading it back."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import flexmbs


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
    assert m["effective_mass_fraction"].shape == (8, 3) and len(m["labels"]) == 8
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
    # mass-normalised modal basis: M_red = I, K_red = diag(omega^2)
    assert np.allclose(body["m_red"], np.eye(8), atol=1e-9)
    assert np.allclose(body["k_red"], np.diag(ref["omega2"]), rtol=1e-8, atol=1e-6 * ref["omega2"].max())
    with pytest.raises(flexmbs.IoError):
        flexmbs.read_body(tmp_path / "missing.fmb.h5")


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
