# xy_loglog.gp: curves of (x, y) points on log-log axes (work-precision diagrams, error versus
# step size).
#
# Usage:
#   gnuplot -c xy_loglog.gp OUT.png TITLE XLABEL YLABEL CURVES [NOTE]
#
# CURVES is a gnuplot file defining the curves (gnuplot -c passes at most 9 arguments):
#   n = 2
#   array file[n]; array label[n]
#   file[1] = "points.dat"; label[1] = "LGVI order 2"
#   file[2] = "points.dat"; label[2] = "cvode-bdf (quaternion)"
#   array colour[n]; array point[n]; array dash[n]      (optional: the curves' styles)
#   colour[1] = "#000000"; point[1] = 7; dash[1] = 1
# Curve i draws data block i-1 (blocks separated by two blank lines) of file[i]: whitespace-
# separated "x y" lines, joined in file order. lgvi-testbed writes only finite positive points
# up to 1e30 (the axes span the data drawn; NOTE, printed in a corner, says how many it left
# out) and the styles of its one palette (experiments/output/
# palette.cpp: a method has the same style in every figure); without them the curves take
# gnuplot's own colours. XLABEL and YLABEL are gnuplot enhanced text; TITLE and the labels are
# printed literally. The terminal and size: terminal.gp.

if (ARGC != 5 && ARGC != 6) {
    print "usage: gnuplot -c xy_loglog.gp OUT.png TITLE XLABEL YLABEL CURVES [NOTE]"
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

set title ARG2 noenhanced
set xlabel ARG3
set ylabel ARG4
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set grid xtics ytics
@key_below font @font_key
set style textbox opaque noborder
if (ARGC == 6) { set label 1 ARG6 noenhanced at graph 0.02, graph 0.95 left front boxed }

plot for [i=1:n] file[i] index (i - 1) using 1:2 \
     with linespoints linewidth 1.2 pointtype point[i] pointsize 0.7 dashtype dash[i] \
     linecolor rgb colour[i] title label[i]
