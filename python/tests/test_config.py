"""Configuration files: save what the card holds, load it into another card."""

from __future__ import annotations

import pathlib

import pytest

import motioncard as mc


def test_save_and_load_round_trip(card: mc.Card, tmp_path: pathlib.Path) -> None:
    card.axis(2).set_scale(250.0)
    text = card.save_config()
    section = text[text.index("[axis.2]") :]
    assert section.splitlines()[1] == "scale = 250.0"
    path = tmp_path / "card.toml"
    card.save_config_file(path)
    assert path.read_text() == text
    with mc.Card.open_sim() as other:
        assert other.axis(2).scale == 1.0
        applied = other.load_config_file(path)
        assert applied, "the scale differed: something was applied"
        assert other.axis(2).scale == 250.0
        assert other.save_config() == text
        # loading it again changes nothing
        assert other.load_config(text, "again") == []


def test_bad_config_is_refused(card: mc.Card) -> None:
    with pytest.raises(mc.ConfigFileError):
        card.load_config("[card]\nservo_rate_hz = 'fast'\n", "bad.toml")
