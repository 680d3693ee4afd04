"""`mechcont study --method form` refuses the freefall-only options instead of ignoring them."""

from cli_helpers import make_runner, one_line_error


def test_study_form_refuses_lock_and_until(tmp_path):
    cli = make_runner()
    for extra, option in ((("--lock", "rest"), "--lock"), (("--until", "1.0"), "--until")):
        r = cli("study", "nose_gear", "--method", "form", "--dist", "LU=normal:1.3:0.01", *extra,
                "--out", tmp_path / "f", "--scheduler", "serial")
        one_line_error(r, option, "--method form")
        assert not (tmp_path / "f").exists()
