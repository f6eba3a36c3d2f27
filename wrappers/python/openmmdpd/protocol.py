"""The main job's protocol, shared by compare (which runs it) and report (which describes it):
the sampling schedule, the blocks behind the errors of r1 and D, and the thresholds of stability."""

R1_BLOCKS = 5              # blocks of g(r) frames whose spread gives the errors of r1 and Nc(r1)
DIFFUSION_GROUPS = 8       # interleaved sets of particles whose spread in D gives its error
DIFFUSION_FIT = (10.0, 30.0)  # the lags (time units) D is fitted over: diffusive, with many origins
CONF_KT_TOLERANCE = 0.1    # a stable run's configurational kT is within 10 % of 1 (soft scene)
CHAIN_KT_TOLERANCE = 0.1   # and its chain <kT> within 10 % of 1 (polymer scene)
# The longest bond a stable polymer run may have: a harmonic bond (k = 7 kT/rc^2, rest length 0)
# has rms length sqrt(3/7) = 0.65 and passes 2.5 with probability 1.7e-9 per bond and sample
# (k r^2 / kT is chi-squared with 3 degrees of freedom: chi2.sf(2.5**2 * 7, 3)).
BOND_LIMIT = 2.5
CORE_RADIUS = 0.2          # g(r < 0.2 rc): pairs overlapping by 80 % (8 kT of repulsion at a = 25)
OVERLAP_EXCESS = 0.2       # how far above the smallest-dt g(r < 0.2 rc) means overlapping particles


def schedule(dt, args):
    """(stride, samples, frame_every) of a run at dt: a sample every ~args.sample_every units of
    time, a frame every ~args.frame_every, args.time in all, whatever dt."""
    stride = max(1, round(args.sample_every / dt))
    samples = max(2, round(args.time / (stride * dt)))
    return stride, samples, max(1, round(args.frame_every / (stride * dt)))
