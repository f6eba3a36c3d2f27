"""Command-line conventions shared by the package's tools."""


def add_quick(parser, quick):
    """--quick: a run of seconds for CI and a first look, with the settings `quick` (a dict of
    option defaults; explicit options still override it)."""
    parser.add_argument("--quick", action="store_true", help=f"a run of seconds for CI: {quick}")


def parse_args(parser, argv, quick):
    """parser's arguments from argv (None: sys.argv), with `quick` as the defaults under --quick."""
    if parser.parse_args(argv).quick:
        parser.set_defaults(**quick)
    return parser.parse_args(argv)
