# xy_bands_loglog.gp: banded curves on log-log axes (an ensemble's work-precision diagrams: per
# method the median over the samples joined across the settings, with the 25-75% quantile band
# shaded and the 5-95% band lighter).
#
# Usage:
#   gnuplot -c xy_bands_loglog.gp OUT.png TITLE XLABEL YLABEL CURVES
#
# CURVES is a gnuplot file defining the curves, as for xy_loglog.gp (n, file[i], label[i],
# colour[i], point[i], dash[i]). Curve i draws data block i-1 (blocks separated by two blank
# lines) of file[i]: whitespace-separated "x median q05 q25 q75 q95" lines, one per setting,
# joined in file order. lgvi-testbed writes only finite positive points up to 1e30. XLABEL and
# YLABEL are gnuplot enhanced text; TITLE and the labels are printed literally. The terminal
# and size: terminal.gp.

if (ARGC != 5) {
    print "usage: gnuplot -c xy_bands_loglog.gp OUT.png TITLE XLABEL YLABEL CURVES"
    exit status 2
}
load ARG5
default_colours = "#9400d3 #009e73 #56b4e9 #e69f00 #f0e442 #0072b2 #e51e10 #000000"
if (!exists("colour")) {
    array colour[n]; array point[n]; array dash[n]
    do for [i=1:n] { colour[i] = word(default_colours, 1 + (i - 1) % 8); point[i] = 1 + (i - 1) % 13; dash[i] = 1 + (i - 1) / 8 }
}

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

plot for [i=1:n] file[i] index (i - 1) using 1:3:6 with filledcurves fillstyle transparent solid 0.10 noborder \
         linecolor rgb colour[i] notitle, \
     for [i=1:n] file[i] index (i - 1) using 1:4:5 with filledcurves fillstyle transparent solid 0.25 noborder \
         linecolor rgb colour[i] notitle, \
     for [i=1:n] file[i] index (i - 1) using 1:2 \
         with linespoints linewidth 1.2 pointtype point[i] pointsize 0.7 dashtype dash[i] \
         linecolor rgb colour[i] title label[i]
