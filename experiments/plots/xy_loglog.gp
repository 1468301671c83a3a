# xy_loglog.gp: curves of (x, y) points on log-log axes (work-precision diagrams, error versus
# step size).
#
# Usage:
#   gnuplot -c xy_loglog.gp OUT.png TITLE XLABEL YLABEL CURVES
#
# CURVES is a gnuplot file defining the curves (gnuplot -c passes at most 9 arguments):
#   n = 2
#   array file[n]; array label[n]
#   file[1] = "points.dat"; label[1] = "LGVI order 2"
#   file[2] = "points.dat"; label[2] = "cvode-bdf (quaternion)"
# Curve i draws data block i-1 (blocks separated by two blank lines) of file[i]: whitespace-
# separated "x y" lines, joined in file order. XLABEL and YLABEL are gnuplot enhanced text;
# TITLE and the labels are printed literally.

if (ARGC != 5) {
    print "usage: gnuplot -c xy_loglog.gp OUT.png TITLE XLABEL YLABEL CURVES"
    exit status 2
}
load ARG5

set terminal pngcairo size 1200,720 enhanced font "sans,11" linewidth 1.5
set output ARG1
set title ARG2 noenhanced
set xlabel ARG3
set ylabel ARG4
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set grid xtics ytics
set key outside right top vertical noenhanced font ",9"

dash(k) = 1 + (k - 1) / 8
point(k) = 1 + (k - 1) % 13

plot for [i=1:n] file[i] index (i - 1) using 1:2 \
     with linespoints linewidth 1.5 pointtype point(i) dashtype dash(i) title label[i]
