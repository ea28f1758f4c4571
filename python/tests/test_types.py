"""Types: the keyword options' TypedDicts (brdfit/_keywords.py) are what
scripts/gen_python_keywords.py makes from the library's option table now; the package and
its examples pass mypy --strict; a user's script with a wrong keyword is flagged."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def test_keywords_module_is_up_to_date(tmp_path):
    out = tmp_path / "_keywords.py"
    subprocess.run([sys.executable, str(REPO / "scripts" / "gen_python_keywords.py"), str(out)], check=True)
    assert out.read_text() == (REPO / "python" / "brdfit" / "_keywords.py").read_text(), (
        "python/brdfit/_keywords.py is out of date: run scripts/gen_python_keywords.py")


def _mypy(cache, *paths):
    """mypy --strict (python/mypy.ini) over paths, the package found in python/."""
    env = dict(os.environ, MYPYPATH=str(REPO / "python"))
    return subprocess.run([sys.executable, "-m", "mypy", "--config-file", str(REPO / "python" / "mypy.ini"),
                           "--cache-dir", str(cache), "--no-error-summary", *map(str, paths)],
                          capture_output=True, text=True, env=env, cwd=REPO)


def test_the_package_and_its_examples_type_check(tmp_path):
    got = _mypy(tmp_path / "cache", REPO / "python" / "brdfit", *sorted((REPO / "examples" / "python").glob("*.py")))
    assert got.returncode == 0, got.stdout + got.stderr


USER_SCRIPT = textwrap.dedent("""\
    import brdfit

    s = brdfit.read("a.csv", rgb=True, subsample=300, negative="clamp")
    r = brdfit.fit(s, "walter", residual="log", starts=4, presolve="off", threads=1, fix="rho_d=0.1")
    c = brdfit.compare([s], "lambert,walter", rank="bic", jobs=2)
    t = brdfit.tradeoff(s, "walter", samples=[300, "all"], methods=["ceres", "LD_LBFGS"])
    k = brdfit.select(s, ["lambert", "walter"], rank="cv", folds=5)
    x: float = r.params["alpha"]
    brdfit.fit(s, "walter", starts="many")
    brdfit.fit(s, "walter", startz=3)
    brdfit.read("a.csv", negative="dropp")
    brdfit.select(s, folds=2.5)
    brdfit.compare([s], "walter", rank="aic", jobs="2")
""")


def test_a_wrong_keyword_is_flagged_where_it_is_written(tmp_path):
    # The keyword options are typed from the library's table (names, value types,
    # choices): a type checker catches a misspelt option or a value of the wrong kind,
    # and only those.
    script = tmp_path / "user.py"
    script.write_text(USER_SCRIPT)
    got = _mypy(tmp_path / "cache", script)
    flagged = sorted({int(line.split(":")[1]) for line in got.stdout.splitlines() if ": error:" in line})
    assert flagged == [9, 10, 11, 12, 13], got.stdout
    assert 'Unexpected keyword argument "startz" for "fit"' in got.stdout
    assert "Literal['keep', 'drop', 'clamp']" in got.stdout
