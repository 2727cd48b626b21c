"""Verifying many certificates (magrod.proof.schedule): on every core, never twice, results in a fixed order.

The cache tests drive a stand-in verifier (counting its calls) in this process: they test what is remembered and
under which key, not the verifier.  The process test runs the real verifier on shipped certificates tampered so
that they are rejected by the cheap structural checks (< 1 s each): the order of the results and each result's
checks must be those of the serial run."""
from __future__ import annotations

import copy
import json
from importlib import resources

import pytest

from magrod.proof import schedule, verify


def _shipped(name):
    return json.loads(resources.files("magrod.proof").joinpath("certificates", name).read_text())


def test_the_trust_base_digest_covers_the_verifier_and_nothing_of_the_provers():
    mods = set(schedule.trust_base_modules())
    assert ({"magrod.proof.verify", "magrod.proof.ball", "magrod.proof.fields", "magrod.proof.taylor",
            "magrod.proof.theorem", "magrod.proof.section_return", "magrod.proof.identities", "magrod.proof.variational",
            "magrod.generated.validated"} | {f"magrod.proof.kernel.{m}" for m in ("schema", "homoclinic", "fixed_point",
                                                                               "horseshoe", "horseshoe_lam2", "pool")}
            <= mods), mods
    assert not mods & {f"magrod.proof.{m}" for m in ("saddle", "manifold", "schedule")}, mods
    assert not {m for m in mods if m.startswith("magrod.proof.provers")}, mods


@pytest.fixture
def fake(monkeypatch):
    calls = []

    def one(cert, inner):
        calls.append(cert["name"])
        ok = cert.get("good", True)
        return verify.VerifyResult(ok, f"verified {cert['name']}" if ok else "rejected", [{"name": "c", "holds": ok,
                                   "how": "x"}], 1.5, f"theorem {cert['name']}" if ok else "", {}, {"v": cert["name"]})

    monkeypatch.setattr(schedule, "_verify_one", one)
    return calls


def test_a_verified_certificate_is_remembered_and_a_changed_one_is_not(tmp_path, fake, monkeypatch):
    certs = [("a", {"name": "a", "x": 1}), ("b", {"name": "b", "x": 2})]
    seen = []
    first = schedule.verify_many(certs, workers=1, cache_dir=tmp_path, progress=lambda *a: seen.append(a))
    assert fake == ["a", "b"] and [s[3] for s in seen] == [False, False]
    seen.clear()
    again = schedule.verify_many(certs, workers=1, cache_dir=tmp_path, progress=lambda *a: seen.append(a))
    assert fake == ["a", "b"] and [s[3] for s in seen] == [True, True]  # nothing verified twice
    assert [r.to_dict() for r in again] == [r.to_dict() for r in first]
    # key order is not content: the same certificate
    schedule.verify_many([("a", {"x": 1, "name": "a"})], workers=1, cache_dir=tmp_path)
    assert fake == ["a", "b"]
    # a changed certificate is verified again
    schedule.verify_many([("a", {"name": "a", "x": 3})], workers=1, cache_dir=tmp_path)
    assert fake == ["a", "b", "a"]
    # a damaged record is not trusted
    for p in tmp_path.iterdir():
        p.write_text(p.read_text().replace('"ok": true', '"ok": false'))
    schedule.verify_many(certs[:1], workers=1, cache_dir=tmp_path)
    assert fake == ["a", "b", "a", "a"]
    # a changed verifier (trust base) verifies everything again
    monkeypatch.setattr(schedule, "trust_base_digest", lambda: "0" * 64)
    schedule.verify_many(certs, workers=1, cache_dir=tmp_path)
    assert fake == ["a", "b", "a", "a", "a", "b"]


def test_a_remembered_result_keeps_its_wall_time_exactly(tmp_path, monkeypatch):
    """The proof figure rounds a verification's wall time to 0.1 s for its sidecar; a remembered result must give the
    same rounding as the fresh one.  Seen to fail when the record kept to_dict's 3-decimal rounding: 7.1496 s was
    7.1 fresh and 7.15 -> 7.2 remembered (test_reproduce's re-run read 7.2 against 7.1)."""
    def one(cert, inner):
        return verify.VerifyResult(True, "verified", [], 7.1496, "theorem", {}, {})

    monkeypatch.setattr(schedule, "_verify_one", one)
    certs = [("a", {"name": "a"})]
    fresh = schedule.verify_many(certs, workers=1, cache_dir=tmp_path)[0]
    again = schedule.verify_many(certs, workers=1, cache_dir=tmp_path)[0]
    assert again.wall_time_s == fresh.wall_time_s and round(again.wall_time_s, 1) == 7.1


def test_a_rejected_certificate_is_never_remembered(tmp_path, fake):
    bad = [("bad", {"name": "bad", "good": False})]
    assert not schedule.verify_many(bad, workers=1, cache_dir=tmp_path)[0].ok
    assert not schedule.verify_many(bad, workers=1, cache_dir=tmp_path)[0].ok
    assert fake == ["bad", "bad"] and not list(tmp_path.iterdir())


def test_processes_give_the_serial_results_in_the_given_order():
    base = _shipped("homoclinic_target.json")
    certs = []
    for i, how in enumerate(("theorem", "target", "settings")):
        c = copy.deepcopy(base)
        if how == "theorem":
            c["theorem"] += " (and more)"
        elif how == "target":
            c["settings"]["targets"] = ["0", "0"]
        else:
            c["settings"]["r"] = "1/3"
        certs.append((f"c{i}", c))
    serial = schedule.verify_many(certs, workers=1)
    parallel = schedule.verify_many(certs, workers=2)
    strip = [{k: v for k, v in r.to_dict().items() if k != "wall_time_s"} for r in serial]
    assert [{k: v for k, v in r.to_dict().items() if k != "wall_time_s"} for r in parallel] == strip
    assert [r.ok for r in serial] == [False] * 3
    assert [r.reason.split(": ", 1)[1].split(" failed")[0] for r in serial] == ["theorem text", "targets distinct",
                                                                                 "settings match the data"]
