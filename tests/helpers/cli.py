"""The command line called in-process, as the hostile-input suites call it."""

from filmscale.workflows.cli import main


def run_main(argv: list[str], capsys) -> tuple[int, str, str]:
    """`main(argv)` with pytest's ``capsys``: (exit status, stdout, stderr); argparse's
    SystemExit (usage errors, --help) gives its code."""
    try:
        code = main(argv)
    except SystemExit as exit_:            # argparse: usage errors, --help
        code = exit_.code
    captured = capsys.readouterr()
    return code, captured.out, captured.err
