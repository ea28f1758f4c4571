"""Types: the keyword options' TypedDicts (brdfit/_keywords.py) are what
python/tools/gen_keywords.py makes from the library's option table now."""

import subprocess
import sys
from pathlib import Path

PYTHON_DIR = Path(__file__).resolve().parents[1]


def test_keywords_module_is_up_to_date(tmp_path):
    out = tmp_path / "_keywords.py"
    subprocess.run([sys.executable, str(PYTHON_DIR / "tools" / "gen_keywords.py"), str(out)], check=True)
    assert out.read_text() == (PYTHON_DIR / "brdfit" / "_keywords.py").read_text(), (
        "brdfit/_keywords.py is out of date: run python/tools/gen_keywords.py")
