# SPDX-License-Identifier: MIT
"""docs/results.md as the measuring scripts write it (scripts/results.sh), and the README's results
table as a copy of its accuracy section."""
import pathlib
import re
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]
# The sections docs/results.md must have and the script that writes each; any further section
# named ablation-* is also ablation.sh's (`--section`).
SECTIONS = {"accuracy": "ablation.sh", "benchmark": "benchmark.sh", "defects": "defects.sh", "ablation": "ablation.sh",
            "sessions": "sessions.sh"}


def sections_of(text):
    named = dict(SECTIONS)
    for name in re.findall(r"^<!-- results:(ablation-[a-z-]+) -->$", text, re.M):
        named[name] = "ablation.sh"
    return named
PROVENANCE = re.compile(r"Written by `scripts/(?P<script>[a-z]+\.sh)[^`]*` on \d{4}-\d\d-\d\d \d\d:\d\d UTC "
                        r"at commit [0-9a-f]{7,}( with uncommitted changes)?, on .+ \(\d+ cores\)\.")


def section(text, name):
    match = re.search(rf"^<!-- results:{name} -->\n(.*?)^<!-- /results:{name} -->$", text, re.S | re.M)
    assert match, f"no section '{name}'"
    return match.group(1)


def test_every_section_is_its_scripts_output():
    doc = (ROOT / "docs" / "results.md").read_text()
    for name, script in sections_of(doc).items():
        lines = section(doc, name).splitlines()
        assert len(lines) >= 5, f"section '{name}' is empty: run scripts/{script}"
        provenance = PROVENANCE.fullmatch(lines[0])
        assert provenance, f"section '{name}': {lines[0]!r}"
        assert provenance["script"] == script
        header = subprocess.run([str(ROOT / "scripts" / script), "--print-header"], check=True,
                                capture_output=True, text=True).stdout.splitlines()
        assert lines[1] == "" and lines[2:4] == header, f"section '{name}' does not start with the header of {script}"
        columns = header[0].count("|")
        rows = [line for line in lines[4:] if line.startswith("| ")]
        assert rows, f"section '{name}' has no rows"
        for row in rows:
            assert row.count("|") == columns, f"section '{name}': {row}"


def test_the_readme_table_is_the_accuracy_section():
    doc = (ROOT / "docs" / "results.md").read_text()
    readme = (ROOT / "README.md").read_text()
    assert section(readme, "accuracy") == section(doc, "accuracy")
