"""The front door a newcomer reads: the README stays short and every file it links to exists;
the citation names the version the package has."""

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


def test_the_readme_is_short_and_its_links_resolve():
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) < 200
    local = [target for target in LINK.findall(text) if "://" not in target]
    assert len(local) > 20
    missing = [target for target in local if not (ROOT / target).exists()]
    assert missing == []


def test_the_citation_names_the_packages_version():
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    citation = (ROOT / "CITATION.cff").read_text()
    assert re.search(rf"^version: {re.escape(version)}$", citation, re.MULTILINE)
    assert "arXiv:2504.15782" in citation


def test_the_readme_carries_the_three_splits_as_the_kept_runs_give_them():
    """The README's table of the tuning, held-out and VTK splits is the one
    docs/split_summary.py makes from the bench runs kept in docs/bench/ (it rewrites it)."""
    import sys

    sys.path.insert(0, str(ROOT / "docs"))
    try:
        import split_summary
    finally:
        sys.path.remove(str(ROOT / "docs"))
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert split_summary.with_table(text) == text
    assert "VTK" in split_summary.table()
