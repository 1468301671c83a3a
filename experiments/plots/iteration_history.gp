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
# COLUMN is read by name (violation, cond_inverted, cond_sensitivity ...) and plotted as its
# absolute value; zeros and non-numbers (nan: not computed at that row) are left out.
# XLABEL and YLABEL are gnuplot enhanced text; TITLE and the labels are printed literally.

if (ARGC != 6) {
    print "usage: gnuplot -c iteration_history.gp OUT.png TITLE XLABEL YLABEL CURVES COLUMN"
    exit status 2
}
load ARG5

set terminal pngcairo size 1200,800 enhanced font "sans,11" linewidth 1.5
set output ARG1
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
set key outside below center vertical maxcols 2 width -8 noenhanced font ",9"

positive(x) = (x > 0 ? x : NaN)
dash(k) = 1 + (k - 1) / 8
point(k) = 1 + (k - 1) % 13

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
     with linespoints linewidth 1.5 pointtype point(i) pointsize 0.8 dashtype dash(i) title label[i]
