# ocp_figure.gp: what the paper's Figs. 2-5 (fig_*.gp) share, loaded by them after setting
# fig_out and fig_title (their ARG1, ARG2) and t_final (the horizon, read from the trajectory).
# It opens the multiplot; the script draws the panels and closes it.
#
# Each figure is drawn for one column of a two-column page: 3.5 in wide, 4.6 in high, 7 pt axis labels
# and 6 pt titles, tick labels and keys (terminal.gp: a PNG at 300 pixels per inch, or PDF, SVG). Four
# panels in a 2 x 2 grid. No gnuplot key: each panel names its curves in one or two rows of
# text in the curves' colours between its title and its axes (labels 101-109, `unset label`
# before the next panel), never over the curves. The time axes have three labelled ticks
# (0, t_final/2, t_final).

fig_width = 3.5
fig_height = 4.6
fig_font = 7
fig_dpi = 300
load plots_dir."terminal.gp"

set datafile separator comma
set datafile commentschars "#"
set datafile columnheaders
positive(x) = (x > 0 ? x : NaN)

set tics font @font_6
set xtics offset 0, 0.3
set ytics offset 0.4, 0
set xlabel offset 0, 0.6
set ylabel offset 0.8, 0
set grid
unset key
# Curve colours (Okabe-Ito): components 1, 2, 3 and a fourth.
c1 = "#0072B2"; c2 = "#D55E00"; c3 = "#009E73"; c4 = "#7F7F7F"
# Every panel's title leaves room for two rows of curve names: row_1 just above the axes,
# row_2 above it (offsets in characters of the labels' centres from the axes' top edge, so the
# rows keep their place in a panel of any height).
set title offset 0, 1.3
# The figure's and the panels' titles in 6 pt: at 7 pt two panel titles side by side run into
# each other and the figure's title takes five lines (figures_command.cpp wraps it at 60
# characters).
set title font @font_6
row_1 = 0.7
row_2 = 1.6
# About four labelled ticks on a value axis: `tic_file = FILE; tic_columns = "c1 c2"; @value_tics`
# spans the columns' range.
value_tics = "lo = 1e300; hi = -1e300; do for [c in tic_columns] { stats tic_file using (column(c)) nooutput; lo = (STATS_min < lo ? STATS_min : lo); hi = (STATS_max > hi ? STATS_max : hi) }; if (hi > lo) { set ytics nice_step((hi - lo) / 4.0) } else { set ytics autofreq }"
time_tics = "set xtics 0, t_final / 2.0, t_final; set mxtics 2; set format x '%.3g'"
# An iteration axis up to n: two to four labelled ticks at round numbers.
iteration_step(n) = (n <= 2.5 ? 1 : nice_step(n / 2.5))
nice_step(m) = 10**floor(log10(m)) * nice_factor(m / 10**floor(log10(m)))
nice_factor(f) = (f <= 1 ? 1 : (f <= 2 ? 2 : (f <= 5 ? 5 : 10)))

set multiplot layout 2,2 title fig_title font @font_6 noenhanced margins 0.19, 0.87, 0.08, 0.72 spacing 0.2, 0.23
