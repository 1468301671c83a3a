# fig_dumbbell.gp: the paper's Fig. 2 for the indirect dumbbell-spacecraft example: (a) the
# maneuver in the orbital plane, (b) the control moment and force, (c) the convergence of the
# shooting with the condition numbers, (d) the angular velocity.
#
# Usage:
#   gnuplot -c fig_dumbbell.gp OUT.png TITLE trajectory.csv history.csv
#
# trajectory.csv and history.csv are the ocp-dumbbell-{trajectory,history}.csv files written by
# `lgvi-testbed ocp dumbbell`; columns are read by name. (a) draws the path of the center of mass
# x in the e1-e2 plane (normalized units: orbit radius 1) and the rod axis R e1 at eleven equally
# spaced times, drawn with a length of 0.1 (the rod is 0.3 long in these units; the scale makes
# the attitude readable).

if (ARGC != 4) {
    print "usage: gnuplot -c fig_dumbbell.gp OUT.png TITLE trajectory.csv history.csv"
    exit status 2
}

set terminal pngcairo size 1400,1000 enhanced font "sans,11" linewidth 1.5
set output ARG1
set datafile separator comma
set datafile commentschars "#"
set datafile columnheaders
positive(x) = (x > 0 ? x : NaN)

stats ARG3 using 1 nooutput
every_snapshot = int((STATS_records - 1) / 10)

set multiplot layout 2,2 title ARG2 noenhanced font "sans,14"

# (a) maneuver
set title "(a) maneuver: center of mass x and rod axis R e_1 (length scaled to 0.1)"
set xlabel "x_1 [normalized]"
set ylabel "x_2 [normalized]"
set size ratio -1
set key top left
rod = 0.1
plot ARG3 using "x1":"x2" with lines lc rgb "#1f77b4" title "x", \
     ARG3 every every_snapshot using (column("x1") - rod/2*column("R11")):(column("x2") - rod/2*column("R21")):(rod*column("R11")):(rod*column("R21")) \
          with vectors nohead lc rgb "#d62728" lw 2 title "R e_1"
set size noratio
set key default

# (b) control moment and force
set title "(b) control moment u^m (body frame) and force u^f (inertial frame)"
set xlabel "t [normalized]"
set ylabel "u [normalized]"
set key top right
set grid
plot ARG3 using "t":"um1" with lines lc 1 title "u^m_1", \
     ARG3 using "t":"um2" with lines lc 2 title "u^m_2", \
     ARG3 using "t":"um3" with lines lc 3 title "u^m_3", \
     ARG3 using "t":"uf1" with lines dt 2 lc 1 title "u^f_1", \
     ARG3 using "t":"uf2" with lines dt 2 lc 2 title "u^f_2", \
     ARG3 using "t":"uf3" with lines dt 2 lc 3 title "u^f_3"

# (c) convergence
set title "(c) convergence of the Newton-Armijo shooting"
set xlabel "outer iteration"
set ylabel "terminal violation"
set logscale y
set format y "10^{%L}"
set y2label "condition number"
set logscale y2
set format y2 "10^{%L}"
set y2tics
set ytics nomirror
set key at graph 0.98, graph 0.75 right opaque box
plot ARG4 using "iteration":(positive(column("violation"))) with linespoints pt 6 lc rgb "#d62728" title "violation (left axis)", \
     ARG4 using "iteration":(positive(column("cond_inverted"))) axes x1y2 with linespoints pt 2 lc rgb "#2ca02c" title "cond of the inverted matrix", \
     ARG4 using "iteration":(positive(column("cond_sensitivity"))) axes x1y2 with linespoints pt 4 lc rgb "#7f7f7f" title "cond of the full sensitivity"
unset logscale y
unset logscale y2
unset y2tics
unset y2label
set ytics mirror
set key default
set format y "%g"

# (d) angular velocity
set title "(d) angular velocity Ω (body frame)"
set xlabel "t [normalized]"
set ylabel "Ω [normalized]"
plot ARG3 using "t":"Omega1" with lines title "Ω_1", \
     ARG3 using "t":"Omega2" with lines title "Ω_2", \
     ARG3 using "t":"Omega3" with lines title "Ω_3"

unset multiplot
