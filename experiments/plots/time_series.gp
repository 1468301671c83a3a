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
# COLUMN is read by name (energy_error, orthogonality_error, quaternion_norm_error,
# momentum_error ...) and plotted as its absolute value; ":logx" makes the time axis
# logarithmic (t = 0 left out). Exact zeros cannot be drawn on a log axis and are left out.
# XLABEL and YLABEL are gnuplot enhanced text; TITLE and the labels are printed literally.

if (ARGC != 6) {
    print "usage: gnuplot -c time_series.gp OUT.png TITLE XLABEL YLABEL CURVES COLUMN[:logx]"
    exit status 2
}
load ARG5

set terminal pngcairo size 1200,720 enhanced font "sans,11" linewidth 1.5
set output ARG1
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
set key outside right top vertical noenhanced font ",9"

positive(x) = (x > 0 ? x : NaN)
time_of(t) = (logx > 0 && t <= 0 ? NaN : t)
dash(k) = 1 + (k - 1) / 8

# A figure whose every curve is exactly 0 at every sample (a quantity conserved to the last
# bit, a body at rest) has no point on the log scale, and gnuplot cannot autoscale an axis
# without one ("all points y value undefined"): count the drawable points first and give such a
# figure a fixed range and a label saying so.
drawn = 0
do for [i=1:n] {
    undefine STATS_records
    stats file[i] using (time_of(column("t"))):(positive(abs(column(column_name)))) nooutput
    if (exists("STATS_records")) { drawn = drawn + STATS_records }
}
if (drawn == 0) { set yrange [1e-16:1]; set label 1 "exactly 0 at every sample" at graph 0.5, 0.5 center }

plot for [i=1:n] file[i] using (time_of(column("t"))):(positive(abs(column(column_name)))) \
     with lines linewidth (i == 1 ? 2.5 : 1.2) dashtype dash(i) title label[i]
