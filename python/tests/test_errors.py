"""Errors raise brdfit.Error with the library's one-line message; usage errors (bad model
specs, bad option values) are also ValueError; bad options as keyword arguments."""

import pytest

import brdfit
from _support import CAYMAN, DATA, DIRS_SMALL, LAMBERT_RGB, cli, message_line


def _cli_message(*args):
    """The command line's one-line error for the same input, without its "brdfit CMD: "."""
    p = cli(*args, ok=False)
    assert p.returncode != 0
    line = p.stderr.strip().splitlines()[-1]
    prefix = f"brdfit {args[0]}: "
    assert line.startswith(prefix)
    return line[len(prefix):]


def _usage_error(fn, *args, naming=None, **kwargs):
    with pytest.raises(brdfit.Error) as e:
        fn(*args, **kwargs)
    assert isinstance(e.value, ValueError), f"{type(e.value).__name__} is not a ValueError: {e.value}"
    msg = message_line(e.value)
    if naming is not None:
        assert naming in msg, f"{msg!r} does not name {naming!r}"
    return msg


def test_error_class():
    assert issubclass(brdfit.Error, Exception)


# --- data errors: the library's message ---------------------------------------------

def test_missing_file(tmp_path):
    path = str(tmp_path / "no_such_file.csv")
    with pytest.raises(brdfit.Error) as e:
        brdfit.read(path)
    msg = message_line(e.value)
    # the library shortens a long path in the middle ("..."), so only its end is sure
    assert "no_such_file.csv" in msg and "cannot open" in msg
    assert _cli_message("fit", path, "-m", "walter") in msg


@pytest.mark.parametrize("content,name", [("1,2\n", "numbers.csv"), ("theta_i,phi_i\n", "short.csv"),
                                          ("", "empty.csv")])
def test_bad_csv_gives_the_librarys_message(tmp_path, content, name):
    path = tmp_path / name
    path.write_text(content)
    with pytest.raises(brdfit.Error) as e:
        brdfit.read(str(path))
    msg = message_line(e.value)
    assert _cli_message("fit", path, "-m", "lambert") in msg


def test_no_value_columns():
    with pytest.raises(brdfit.Error) as e:
        brdfit.read(str(DIRS_SMALL))
    msg = message_line(e.value)
    assert "no value columns" in msg
    assert _cli_message("fit", DIRS_SMALL, "-m", "lambert") in msg


def test_not_a_data_file():
    with pytest.raises(brdfit.Error) as e:
        brdfit.read(str(LAMBERT_RGB))
    assert _cli_message("fit", LAMBERT_RGB, "-m", "lambert") in message_line(e.value)


def test_grid_needs_a_format_that_can_be_evaluated():
    with pytest.raises(brdfit.Error) as e:
        brdfit.read(str(CAYMAN), grid="merl")
    msg = message_line(e.value)
    assert "merl" in msg


def test_directions_zero_or_nan_are_refused():
    import numpy as np
    wi = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]])
    wo = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    with pytest.raises((brdfit.Error, ValueError)) as e:
        brdfit.Model("lambert").eval(wi, wo, {"rho_d": 0.5})
    message_line(e.value)
    with pytest.raises((brdfit.Error, ValueError)):
        brdfit.Samples(np.array([[0.0, np.nan, 1.0]]), np.array([[0.0, 0.0, 1.0]]), np.array([[1.0]]))


# --- usage errors: brdfit.Error and ValueError ---------------------------------------

def test_unknown_model():
    _usage_error(brdfit.Model, "nosuch", naming="nosuch")
    _usage_error(brdfit.Model, "nosuch", channels=3, naming="nosuch")


def test_bad_model_specs():
    _usage_error(brdfit.Model, "walter:fresnel=bogus", naming="bogus")
    _usage_error(brdfit.Model, "walter:lobes=99", naming="99")
    _usage_error(brdfit.Model, "walter:nosuchoption=1", naming="nosuchoption")
    _usage_error(brdfit.Model, "walter", channels=0)
    _usage_error(brdfit.Model, "walter", channels=100000)


@pytest.mark.parametrize("kw,naming", [
    ({"residual": "bogus"}, "bogus"),
    ({"loss": "bogus"}, "bogus"),
    ({"backend": "bogus"}, "bogus"),
    ({"algorithm": "bogus"}, "bogus"),
    ({"accuracy": "bogus"}, "bogus"),
    ({"starts": 0}, "starts"),
    ({"max_iterations": -5}, None),
])
def test_bad_fit_options(cayman, kw, naming):
    _usage_error(brdfit.fit, cayman, "walter", naming=naming, **kw)


def test_bad_fit_model(cayman):
    _usage_error(brdfit.fit, cayman, "nosuch", naming="nosuch")
    _usage_error(brdfit.fit, cayman, "walter:fresnel=bogus", naming="bogus")


def test_fix_unknown_parameter(cayman):
    for form in ({"bogus": 1.0}, ["bogus=1"]):
        try:
            brdfit.fit(cayman, "walter", fix=form, starts=1)
        except TypeError:
            continue
        except ValueError as e:
            assert isinstance(e, brdfit.Error)
            assert "bogus" in message_line(e)
            return
        pytest.fail("fix= of an unknown parameter did not raise")
    pytest.fail("fix= took neither a dict nor a list of NAME=VALUE")


def test_inverted_bound(cayman):
    for form in ({"alpha": (0.5, 0.1)}, ["alpha=0.5:0.1"]):
        try:
            brdfit.fit(cayman, "walter", bound=form, starts=1)
        except TypeError:
            continue
        except ValueError as e:
            assert isinstance(e, brdfit.Error)
            message_line(e)
            return
        pytest.fail("an inverted bound= did not raise")
    pytest.fail("bound= took neither a dict nor a list of NAME=LO:HI")


@pytest.mark.parametrize("kw,naming", [
    ({"color": "bogus"}, "bogus"),
    ({"max_theta": 0}, None),
    ({"subsample": 0}, None),
    ({"subsample": -3}, None),
    ({"format": "bogus"}, "bogus"),
    ({"negative": "bogus"}, "bogus"),
    ({"illuminant": "bogus"}, "bogus"),
])
def test_bad_data_options(kw, naming):
    _usage_error(brdfit.read, str(CAYMAN), naming=naming, **kw)


def test_unknown_keyword_arguments(cayman):
    for fn, args in ((brdfit.read, (str(CAYMAN),)), (brdfit.fit, (cayman, "walter"))):
        with pytest.raises((TypeError, ValueError)) as e:
            fn(*args, no_such_option=1)
        assert "no_such_option" in str(e.value)


def test_compare_usage_errors(cayman):
    _usage_error(brdfit.compare, [cayman], ["nosuch"], naming="nosuch")
    _usage_error(brdfit.compare, [cayman], ["walter"], rank="bogus", naming="bogus")
    with pytest.raises(ValueError):
        brdfit.compare([], ["walter"])


def test_library_works_after_errors(cayman):
    with pytest.raises(ValueError):
        brdfit.fit(cayman, "walter", residual="bogus")
    with pytest.raises(brdfit.Error):
        brdfit.read(str(DATA / "does_not_exist.csv"))
    r = brdfit.fit(cayman, "lambert", starts=1)
    assert r.metrics["n"] == 3 * 1439
