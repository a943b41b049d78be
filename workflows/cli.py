"""The `filmscale` command line: a thin layer over the library.

Each command family is a module of `COMMANDS` that adds its own sub-parser(s)
(``add_arguments(subparsers)``, each setting its ``func``) and holds its command bodies
(``cmd_*``); this module assembles them, reads a negative number after an option as that
option's value (`Parser`) and turns every failure into one line and an exit status.

Exit status: 0 success; 2 bad input (one line naming the field, no traceback); 1 a valid
question the model cannot answer (an approach that would exceed the sphere radius), or a
LAMMPS run that stopped with an error (its message and run directory).
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import sys

from filmscale.core.errors import FilmscaleError, InputError
from filmscale.core.files import shown

from . import (calibrate_cli, impact_cli, indent_cli, md_cli, particles_cli, pipeline_cli,
               slide_cli)
from .quantity_args import convert_quantities

# The physics (scipy), the scene reader and the result files are imported inside each command,
# so that `filmscale --help` and a usage error answer without loading them.

#: the command families, in the order `filmscale --help` lists their commands: impact and
#: impact-map; slide and slide-map; indent (analyze, calibrate, reverse); calibrate; md and
#: potentials; particles; the scene pipeline's plan, run, sweep, cancel, status and report
COMMANDS = (impact_cli, slide_cli, indent_cli, calibrate_cli, md_cli, particles_cli,
            pipeline_cli)

#: what is read as the value of the option before it, not as an option: a negative number in
#: any form float() reads (-5e6, -1e-9, -.5, -inf) and a range or list that starts with one
#: (-1:1:3); argparse's own pattern (Python 3.11) knows only -5 and -.5
NEGATIVE_VALUE = re.compile(r"^-(\.?\d|inf|nan)", re.IGNORECASE)


class _Version(argparse.Action):
    """--version, reading the version only when asked (importlib.metadata is slow)."""

    def __call__(self, parser, namespace, values, option_string=None):
        from filmscale import __version__
        print(f"filmscale {__version__}")
        parser.exit()


class Parser(argparse.ArgumentParser):
    """filmscale's argument parser, subcommands included: a negative number after an option
    that takes a value is that value (`joined_values`; the range checks then judge it), and a
    usage error is one line.

    Each parser notes whether each of its options takes a value (``takes_value``, its
    groups' options included) and joins the arguments it parses itself; a sub-command's
    arguments reach its own parser whole, which joins them with its own options."""

    def __init__(self, *args, **kwargs):
        #: option string -> whether it takes a value (set before argparse adds --help)
        self.takes_value: dict[str, bool] = {}
        super().__init__(*args, **kwargs)

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")

    # -- what each option takes

    def add_argument(self, *args, **kwargs):
        return self._noted(super().add_argument(*args, **kwargs))

    def add_argument_group(self, *args, **kwargs):
        return self._noting(super().add_argument_group(*args, **kwargs))

    def add_mutually_exclusive_group(self, **kwargs):
        return self._noting(super().add_mutually_exclusive_group(**kwargs))

    def _noted(self, action: argparse.Action) -> argparse.Action:
        for option in action.option_strings:
            self.takes_value[option] = action.nargs != 0
        return action

    def _noting(self, group):
        """``group``, whose options are noted as the parser's own are."""
        add = group.add_argument

        def add_argument(*args, **kwargs):
            return self._noted(add(*args, **kwargs))
        group.add_argument = add_argument
        return group

    # -- negative numbers as values

    def parse_known_args(self, args=None, namespace=None):
        args = sys.argv[1:] if args is None else list(args)
        return super().parse_known_args(self.joined_values(args), namespace)

    def joined_values(self, argv: list[str]) -> list[str]:
        """``argv`` with each negative number (`NEGATIVE_VALUE`) that follows an option of
        this parser taking a value joined to it, ``--option=VALUE``: the form argparse always
        reads as that option's value (``--angle -5e6`` it would take for two options).
        Nothing after ``--`` is joined."""
        out: list[str] = []
        for token in argv:
            if out and "--" not in out and NEGATIVE_VALUE.match(token) \
                    and self._is_value_option(out[-1]):
                out[-1] = f"{out[-1]}={token}"
            else:
                out.append(token)
        return out

    def _is_value_option(self, token: str) -> bool:
        """Whether ``token`` is an option of this parser that takes a value, or the
        abbreviation of one (``--vel``: one option only, as argparse reads it)."""
        if token in self.takes_value:
            return self.takes_value[token]
        if not (self.allow_abbrev and token.startswith("--")) or "=" in token:
            return False
        options = [option for option in self.takes_value if option.startswith(token)]
        return len(options) == 1 and self.takes_value[options[0]]


def build_parser() -> argparse.ArgumentParser:
    """The parser of every command: each family of `COMMANDS` adds its own."""
    parser = Parser(
        prog="filmscale",
        description="Multiscale contact, indentation and impact analysis of thin films.")
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="show the version and exit")
    sub = parser.add_subparsers(dest="command", required=True)
    for family in COMMANDS:
        family.add_arguments(sub)
    return parser


def main(argv=None) -> int:
    """The command line: returns the exit status (0 done, 2 bad input, 1 a model or engine
    failure, 130 interrupted); every failure is one line on stderr, never a traceback."""
    parser = build_parser()
    args = parser.parse_args(argv)
    # a batch system stops a job with SIGTERM: end as Ctrl-C does, so that MPI children
    # are terminated and no half-written file is kept
    previous = signal.signal(signal.SIGTERM, _terminated)
    try:
        convert_quantities(args)
        return args.func(args)
    except FilmscaleError as err:
        kind = "error: " if isinstance(err, InputError) else ""
        print(f"filmscale: {kind}{err}", file=sys.stderr)
        return err.exit_code
    except OSError as err:          # reading or writing a file: permissions, full disk, ...
        where = f"{shown(err.filename)}: " if err.filename else ""
        print(f"filmscale: error: {where}{err.strerror or err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("filmscale: interrupted; nothing half-written was kept", file=sys.stderr)
        return 130
    except Exception as err:        # a defect of filmscale: one line, the traceback on request
        if os.environ.get("FILMSCALE_DEBUG"):
            raise
        print(f"filmscale: internal error ({type(err).__name__}: {err}); rerun with "
              "FILMSCALE_DEBUG=1 for the traceback and please report it", file=sys.stderr)
        return 1
    finally:
        signal.signal(signal.SIGTERM, previous)


def _terminated(signum, frame):
    raise KeyboardInterrupt


if __name__ == "__main__":
    sys.exit(main())
