"""Steps per second, scaling and memory of our integrators against OpenMM's LangevinMiddleIntegrator.

Scene `soft` (model B); one subcommand per kind of measurement, each in a module of its own
(the timing they share is bench_timing's):

    python3 -m openmmdpd.bench rates [--soft-force]      # bench_rates: steps/s at sizes and threads
    python3 -m openmmdpd.bench scale [--platform OpenCL] # bench_scale: 4000 to a million particles
    python3 -m openmmdpd.bench thread-scaling            # bench_threads, bench_copies: threads and their ceiling
    python3 -m openmmdpd.bench memory                    # bench_memory: bytes per particle of a Context
    python3 -m openmmdpd.bench staggered                 # bench_staggered: StaggeredDPDIntegrator against K
    python3 -m openmmdpd.bench sentinel                  # bench_costs: what the instability sentinel costs
    python3 -m openmmdpd.bench shear --rate 0.1          # bench_costs: what Lees-Edwards shear costs
    python3 -m openmmdpd.bench weight-exponent           # bench_costs: what a weight exponent other than 2 costs
    python3 -m openmmdpd.bench exceptions                # bench_costs: what thermostat exceptions cost

`python3 -m openmmdpd.bench MODE --help` gives a mode's options, their defaults and how long
a run with them takes.
"""
from . import bench_costs, bench_memory, bench_rates, bench_scale, bench_staggered, bench_threads, options

DURATION = ("Each mode below gives its defaults and how long a run with them takes on 2 cores, from about half "
            "a minute to roughly 10 minutes; MODE --help gives its options and says more.")


def _parser():
    parser = options.parser("bench", __doc__.splitlines()[0], DURATION)
    modes = parser.add_subparsers(title="modes", dest="mode", metavar="MODE", required=True)
    for module in (bench_rates, bench_scale, bench_threads, bench_memory, bench_staggered, bench_costs):
        module.add_parsers(modes)
    return parser


def main(argv=None):
    args = _parser().parse_args(argv)
    args.run(args)


if __name__ == "__main__":
    main()
