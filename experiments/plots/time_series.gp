# time_series.gp: one column of lgvi-testbed CSVs against time, logarithmic y axis.
#
# Usage:
#   gnuplot -c time_series.gp OUT.png TITLE XLABEL YLABEL CURVES COLUMN[:logx]
#
# CURVES is a gnuplot file defining the curves (gnuplot -c passes at most 9 arguments, so the
# list of CSVs cannot be on the command line):
#   n = 2
#   array file[n]; array label[n]
#   file[1] = "run1.csv"; label[1] = "LGVI order 2"
#   file[2] = "run2.csv"; label[2] = "odeint-rk4 (quaternion)"
#   array colour[n]; array point[n]; array dash[n]      (optional: the curves' styles)
#   colour[1] = "#000000"; point[1] = 7; dash[1] = 1
# COLUMN is read by name (energy_error, orthogonality_error, quaternion_norm_error,
# momentum_error ...) and plotted as its absolute value; ":logx" makes the time axis
# logarithmic (t = 0 left out). Exact zeros cannot be drawn on a log axis and are left out, and
# so are values above 1e30 (a run that diverged without stopping: drawn, they would stretch the
# axis over a hundred decades); the figure says how many. Each curve carries ten markers (its
# palette style, experiments/output/palette.cpp) so curves of one colour stay apart.
# XLABEL and YLABEL are gnuplot enhanced text; TITLE and the labels are printed literally. The
# terminal and size: terminal.gp.

if (ARGC != 6) {
    print "usage: gnuplot -c time_series.gp OUT.png TITLE XLABEL YLABEL CURVES COLUMN[:logx]"
    exit status 2
}
load ARG5
default_colours = "#9400d3 #009e73 #56b4e9 #e69f00 #f0e442 #0072b2 #e51e10 #000000"
if (!exists("colour")) {
    array colour[n]; array point[n]; array dash[n]
    do for [i=1:n] { colour[i] = word(default_colours, 1 + (i - 1) % 8); point[i] = 1 + (i - 1) % 13; dash[i] = 1 + (i - 1) / 8 }
}

# The shared files (terminal.gp ...) are loaded from this script's directory.
plots_dir = ARG0
while (strlen(plots_dir) > 0 && plots_dir[strlen(plots_dir):] ne "/") { plots_dir = plots_dir[:strlen(plots_dir)-1] }
fig_out = ARG1
fig_width = 6.5
n_keys = n
key_maxlen = 0
do for [i=1:n] { key_maxlen = (strlen(label[i]) > key_maxlen ? strlen(label[i]) : key_maxlen) }
load plots_dir."key_layout.gp"
load plots_dir."terminal.gp"
set datafile separator comma
set datafile commentschars "#"
set datafile columnheaders

spec = ARG6
logx = strstrt(spec, ":logx")
column_name = (logx > 0 ? spec[1:logx-1] : spec)

set title ARG2 noenhanced
set xlabel ARG3
set ylabel ARG4
set logscale y
set format y "10^{%L}"
if (logx > 0) { set logscale x; set format x "10^{%L}" }
set grid xtics ytics
set autoscale xfix
@key_below font @font_key

overflow = 1e30
positive(x) = (x > 0 && x <= overflow ? x : NaN)
time_of(t) = (logx > 0 && t <= 0 ? NaN : t)

# A figure whose every curve is exactly 0 at every sample (a quantity conserved to the last
# bit, a body at rest) has no point on the log scale, and gnuplot cannot autoscale an axis
# without one ("all points y value undefined"): count the drawable points first and give such a
# figure a fixed range and a label saying so. Values above `overflow` are counted too.
drawn = 0
over = 0
do for [i=1:n] {
    undefine STATS_records
    stats file[i] using (time_of(column("t"))):(positive(abs(column(column_name)))) nooutput
    if (exists("STATS_records")) { drawn = drawn + STATS_records }
    undefine STATS_records
    stats file[i] using (time_of(column("t"))):(abs(column(column_name)) > overflow ? 1 : NaN) nooutput
    if (exists("STATS_records")) { over = over + STATS_records }
}
if (drawn == 0) { set yrange [1e-16:1]; set label 1 "exactly 0 at every sample" at graph 0.5, 0.5 center }
set style textbox opaque noborder
if (over > 0) { set label 2 sprintf("%d values above 1e30 not drawn", over) at graph 0.02, graph 0.95 left front boxed }

plot for [i=1:n] file[i] using (time_of(column("t"))):(positive(abs(column(column_name)))) \
     with linespoints linewidth 1.2 pointtype point[i] pointsize 0.7 pointnumber 10 dashtype dash[i] \
     linecolor rgb colour[i] title label[i]
