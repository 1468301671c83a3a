# ocp_convergence.gp: terminal violation of the indirect shooting versus sweeps (the paper's
# Figs. 2(b), 3(c): outer iterations as points, every sweep, backtracking trials included, on
# the x axis).
#
# Usage:
#   gnuplot -c ocp_convergence.gp OUT.png TITLE XLABEL YLABEL history1.csv label1 [history2.csv label2 ...]
#
# One curve per ocp-SYSTEM-history.csv written by `lgvi-testbed ocp`; the columns "sweeps" (the
# cumulative number of sweeps at the end of the outer iteration) and "violation" (at its start)
# are read by name. The violation of outer iteration k is drawn at the sweeps spent before it.
# XLABEL and YLABEL are gnuplot enhanced text; TITLE and the curve labels are printed literally.
# The terminal and size: terminal.gp.

if (ARGC < 6 || ARGC % 2 != 0) {
    print "usage: gnuplot -c ocp_convergence.gp OUT.png TITLE XLABEL YLABEL history1.csv label1 [...]"
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

positive(x) = (x > 0 ? x : NaN)
# Sweeps spent before outer iteration k: the previous row's cumulative count (1 before the first).
# column(0) is the row index within each file, so every curve restarts at 1.
previous = 1
before(s) = (column(0) == 0 ? (previous = s, 1) : (p = previous, previous = s, p))

plot for [i=5:ARGC:2] ARGV[i] using (before(column("sweeps"))):(positive(column("violation"))) \
     with linespoints pointtype 7 pointsize 0.8 title ARGV[i+1]
