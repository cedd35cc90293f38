"""Shared fixtures: the repository's example models."""

from __future__ import annotations

from pathlib import Path

import pytest

import flexmbs

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "examples" / "mbs"


@pytest.fixture
def pendulum() -> flexmbs.Model:
    """The shipped rigid double pendulum."""
    return flexmbs.load(EXAMPLES / "double_pendulum.toml")


@pytest.fixture
def spring() -> flexmbs.Model:
    """The shipped spring-damper oscillator (analytic solution known)."""
    return flexmbs.load(EXAMPLES / "spring_damper.toml")
