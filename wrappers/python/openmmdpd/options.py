"""Command-line conventions shared by the package's tools."""
import argparse


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """--help shows each option's default after its help, lists as they are typed ("0.02 0.03");
    a default of None or a flag's False is left out (the help says what happens then)."""

    def _get_help_string(self, action):
        text = action.help or ""
        default = action.default
        if (not action.option_strings or default is None or default is False or default is argparse.SUPPRESS
                or "%(default)" in text):
            return text
        shown = " ".join(map(str, default)) if isinstance(default, (list, tuple)) else str(default)
        return f"{text} (default: {shown.replace('%', '%%')})".lstrip()


def parser(module, description, duration):
    """The ArgumentParser of `python3 -m openmmdpd.MODULE`, whose --help gives `description`, then
    `duration` (how long a run with the defaults takes), then every option with its default."""
    return argparse.ArgumentParser(prog=f"python3 -m openmmdpd.{module}", formatter_class=HelpFormatter,
                                   description=f"{description.strip()} {duration.strip()}")


def add_quick(parser, quick):
    """--quick: a run of seconds for CI and a first look, with the settings `quick` (a dict of
    option defaults; explicit options still override it)."""
    shown = ", ".join(f"--{k.replace('_', '-')} {' '.join(map(str, v)) if isinstance(v, list) else v}"
                      for k, v in quick.items())
    parser.add_argument("--quick", action="store_true", help=f"a run of seconds for CI: {shown}")


def parse_args(parser, argv, quick):
    """parser's arguments from argv (None: sys.argv), with `quick` as the defaults under --quick."""
    if parser.parse_args(argv).quick:
        parser.set_defaults(**quick)
    return parser.parse_args(argv)


def not_a_command(module, instead, argv=None):
    """`python3 -m openmmdpd.MODULE` of a module that is a library: --help says so and what to
    run instead (exit status 0); anything else says the same and exits with status 2."""
    text = f"openmmdpd.{module} is a library module, not a command. {instead}"
    parser = argparse.ArgumentParser(prog=f"python3 -m openmmdpd.{module}", description=text)
    parser.parse_args(argv)
    parser.exit(2, f"{parser.prog}: {text}\n")
