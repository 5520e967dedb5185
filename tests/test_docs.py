"""The README and the documentation pages: short, about the product, and complete where
other files depend on them (``make docs`` builds the site itself, warnings as errors)."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.parts and "_intersphinx" not in p.parts)
# words of a development diary, not of a product's documentation
DIARY = re.compile(r"\b(issue \d+|issue #\d+|sessions?|sittings?)\b", re.IGNORECASE)


def test_readme_reads_in_five_minutes():
    lines = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 150, f"README.md has {len(lines)} lines; keep it to 150 and move the rest into docs/"


@pytest.mark.parametrize("path", [ROOT / "README.md", *PAGES], ids=lambda p: str(p.relative_to(ROOT)))
def test_pages_describe_the_product_not_its_history(path):
    text = path.read_text(encoding="utf-8")
    found = sorted({m.group(0) for m in DIARY.finditer(text)})
    assert not found, f"{path.relative_to(ROOT)} mentions {found}"


def test_every_benchmark_script_has_its_table_in_the_docs():
    text = "\n".join(p.read_text(encoding="utf-8") for p in PAGES)
    missing = [p.name for p in sorted((ROOT / "benchmarks").glob("*.py")) if f"benchmarks/{p.name}" not in text]
    assert not missing, f"benchmark scripts without a page in docs/: {missing}"


def test_readme_links_point_at_files_that_exist():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    targets = [t for t in re.findall(r"\]\(([^)#\s]+)", text) if "://" not in t]
    assert targets
    missing = [t for t in targets if not (ROOT / t).exists()]
    assert not missing, f"README.md links to missing files: {missing}"
