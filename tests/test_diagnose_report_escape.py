"""The diagnosis report's text is escaped exactly once (it comes from the templates)."""

from __future__ import annotations

from pipelines.diagnosis.report.single import _verdict_html, inputs_html


def test_inputs_and_verdict_text_escaped_once():
    inp = dict(
        sigma0_Pa=2e5,
        q0_per_m=1e3,
        q1_per_m=1e5,
        temperature_C=20.0,
        psd_scale=1.0,
        assumed=["sigma0_Pa"],
        uncertain={},
        files=[dict(role="psd", path="a&b<c>.csv", sha256="0" * 64)],
        notes=["x < y & z"],
    )
    out = inputs_html(inp)
    assert "a&amp;b&lt;c&gt;.csv" in out and "&amp;amp;" not in out
    assert "<p><b>Note:</b> x &lt; y &amp; z.</p>" in out
    v = _verdict_html(dict(effect="a<b", reason="r & s", confidence="low", next="measure <T>"))
    assert v.startswith("<p><b>Verdict:</b> a&lt;b. r &amp; s. Confidence: low.</p>")
    assert "<p><b>What to measure next:</b> measure &lt;T&gt;.</p>" in v
    assert inputs_html(None) == "<p>inputs not recorded</p>"
