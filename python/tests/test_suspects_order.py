"""Diagnosis.suspects puts what the diagnosis recommends first and the held-out suspects of a split
that was set aside last, whatever their z (issue 35: a set-aside electromechanical_coupling at z
61.5 topped d.suspects, stdout and the suspects table while the recommendation was elsewhere)."""
from vehs.compute import ranked_suspects


def test_recommended_first_set_aside_last():
    result = {
        "recommended": ["coulomb_friction"],
        "suspects_heldout": {"set_aside": "the held-out split is too coarse"},
        "suspects": [{"effect": "electromechanical_coupling", "z": 61.5, "significant": True},
                     {"effect": "coulomb_friction", "z": 3.0, "significant": False}],
        "score_suspects": [{"effect": "quadratic_damping", "z": 9.0, "significant": True},
                           {"effect": "coulomb_friction", "z": 7.0, "significant": True},
                           {"effect": "impact_stop", "z": 0.5, "significant": False}],
    }
    s = ranked_suspects(result)
    assert [(e["effect"], e["status"]) for e in s] == [
        ("coulomb_friction", "recommended"), ("quadratic_damping", "significant"),
        ("impact_stop", "not significant"), ("electromechanical_coupling", "set aside")]
    assert s[0]["source"] == "score test"


def test_without_a_split_set_aside_held_out_evidence_counts():
    result = {"recommended": [], "suspects": [{"effect": "colored_noise", "z": 5.0, "significant": True}],
              "score_suspects": [{"effect": "impact_stop", "z": 1.0, "significant": False}]}
    assert [e["status"] for e in ranked_suspects(result)] == ["significant", "not significant"]
