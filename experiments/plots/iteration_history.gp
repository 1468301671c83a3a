# iteration_history.gp: one column of solver iteration histories (CSV with an "iteration"
# column) against the iteration, logarithmic y axis: convergence histories and condition
# numbers of the optimal-control solvers.
#
# Usage:
#   gnuplot -c iteration_history.gp OUT.png TITLE XLABEL YLABEL CURVES COLUMN
#
# CURVES is a gnuplot file defining the curves (gnuplot -c passes at most 9 arguments):
#   n = 2
#   array file[n]; array label[n]
#   file[1] = "a-history.csv"; label[1] = "discrete, decomposed (pendulum)"
#   array colour[n]; array point[n]; array dash[n]      (optional: the curves' styles)
#   colour[1] = "#000000"; point[1] = 7; dash[1] = 1
# COLUMN is read by name (violation, cond_inverted, cond_sensitivity ...) and plotted as its
# absolute value; zeros and non-numbers (nan: not computed at that row) are left out.
# XLABEL and YLABEL are gnuplot enhanced text; TITLE and the labels are printed literally. The
# terminal and size: terminal.gp.

if (ARGC != 6) {
    print "usage: gnuplot -c iteration_history.gp OUT.png TITLE XLABEL YLABEL CURVES COLUMN"
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
set datafile missing "nan"

column_name = ARG6

set title ARG2 noenhanced
set xlabel ARG3
set ylabel ARG4
set logscale y
set format y "10^{%L}"
set grid xtics ytics
@key_below font @font_key

positive(x) = (x > 0 ? x : NaN)

# A figure whose every curve is exactly 0 at every sample (a quantity conserved to the last
# bit, a body at rest) has no point on the log scale, and gnuplot cannot autoscale an axis
# without one ("all points y value undefined"): count the drawable points first and give such a
# figure a fixed range and a label saying so.
drawn = 0
do for [i=1:n] {
    undefine STATS_records
    stats file[i] using (column("iteration")):(positive(abs(column(column_name)))) nooutput
    if (exists("STATS_records")) { drawn = drawn + STATS_records }
}
if (drawn == 0) { set yrange [1e-16:1]; set label 1 "exactly 0 at every sample" at graph 0.5, 0.5 center }

plot for [i=1:n] file[i] using (column("iteration")):(positive(abs(column(column_name)))) \
     with linespoints linewidth 1.2 pointtype point[i] pointsize 0.7 dashtype dash[i] linecolor rgb colour[i] \
     title label[i]
