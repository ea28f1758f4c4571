"""Types: the keyword options' TypedDicts (brdfit/_keywords.py) are what
scripts/gen_python_keywords.py makes from the library's option table now."""

import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def test_keywords_module_is_up_to_date(tmp_path):
    out = tmp_path / "_keywords.py"
    subprocess.run([sys.executable, str(REPO / "scripts" / "gen_python_keywords.py"), str(out)], check=True)
    assert out.read_text() == (REPO / "python" / "brdfit" / "_keywords.py").read_text(), (
        "python/brdfit/_keywords.py is out of date: run scripts/gen_python_keywords.py")
