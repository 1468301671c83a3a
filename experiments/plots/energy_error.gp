# energy_error.gp: energy error |E - E0| versus time, log scale.
#
# Usage:
#   gnuplot -c energy_error.gp OUT.png TITLE XLABEL YLABEL in1.csv label1 [in2.csv label2 ...]
#
# One curve per CSV written by lgvi-testbed. The columns "t" and "energy_error" are read by name:
# the CSV's '#' metadata lines are comments to gnuplot, its single header row gives the column
# names (set datafile columnheaders).
# Plots |energy_error| = |E - E0|, the absolute energy error in the scene's energy unit.
# It is exactly 0 at t = 0 (and may be elsewhere): those points are left out.
# XLABEL and YLABEL are gnuplot enhanced text (^ superscript, _ subscript); TITLE and the curve
# labels are printed literally. The terminal and size: terminal.gp.

if (ARGC < 6 || ARGC % 2 != 0) {
    print "usage: gnuplot -c energy_error.gp OUT.png TITLE XLABEL YLABEL in1.csv label1 [in2.csv label2 ...]"
    exit status 2
}

# The shared files (terminal.gp ...) are loaded from this script's directory.
plots_dir = ARG0
while (strlen(plots_dir) > 0 && plots_dir[strlen(plots_dir):] ne "/") { plots_dir = plots_dir[:strlen(plots_dir)-1] }
fig_out = ARG1
fig_width = 6.5
n_keys = (ARGC - 4) / 2
key_maxlen = 0
do for [i=6:ARGC:2] { key_maxlen = (strlen(ARGV[i]) > key_maxlen ? strlen(ARGV[i]) : key_maxlen) }
load plots_dir."key_layout.gp"
load plots_dir."terminal.gp"
set datafile separator comma
set datafile commentschars "#"
set datafile columnheaders

set title ARG2 noenhanced
set xlabel ARG3
set ylabel ARG4
set logscale y
set format y "10^{%L}"
set mytics 10
set grid xtics ytics
@key_below font @font_key
set autoscale xfix

# log(0) does not exist: exact zeros become NaN (left out) instead of an arbitrary floor.
positive(x) = (x > 0 ? x : NaN)

# A figure whose every curve is exactly 0 at every sample (a quantity conserved to the last
# bit, a body at rest) has no point on the log scale, and gnuplot cannot autoscale an axis
# without one ("all points y value undefined"): count the drawable points first and give such a
# figure a fixed range and a label saying so.
drawn = 0
do for [i=5:ARGC:2] {
    undefine STATS_records
    stats ARGV[i] using "t":(positive(abs(column("energy_error")))) nooutput
    if (exists("STATS_records")) { drawn = drawn + STATS_records }
}
if (drawn == 0) { set yrange [1e-16:1]; set label 1 "exactly 0 at every sample" at graph 0.5, 0.5 center }

# The first curve is drawn wider so that a later curve lying on top of it (e.g. the free body,
# where the symmetric and printed forms coincide) leaves it visible.
plot for [i=5:ARGC:2] ARGV[i] using "t":(positive(abs(column("energy_error")))) \
     with lines linewidth (i == 5 ? 2.5 : 1.2) title ARGV[i+1]
