# fig_connected_bodies.gp: the paper's Fig. 5 for the direct two-connected-bodies example: (a) the
# maneuver, (b) the control moment with its knots, (c) the convergence of SLSQP, (d) the angular
# velocities.
#
# Usage:
#   gnuplot -c fig_connected_bodies.gp OUT.png TITLE trajectory.csv history.csv knots.csv
#
# The files are ocp-connected-bodies-{trajectory,history,knots}.csv written by
# `lgvi-testbed ocp connected-bodies`; columns are read by name. (a) draws the paths of the tips
# of the body-fixed unit vectors R1 e1 (body 1) and R2 e1 (body 2) in the inertial frame, with
# the vectors at eleven equally spaced times: the maneuver turns both bodies by 180 deg about e1
# and leaves their relative attitude unchanged.

if (ARGC != 5) {
    print "usage: gnuplot -c fig_connected_bodies.gp OUT.png TITLE trajectory.csv history.csv knots.csv"
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
set title "(a) maneuver: body axes R_1 e_1, R_2 e_1"
set xlabel "e_1"
set ylabel "e_2"
set zlabel "e_3"
set view 62, 30, 1.25, 1
set xyplane at -1.1
set xtics 0.5
set ytics 0.5
set ztics 0.5
set key at screen 0.03, screen 0.92 left
splot ARG3 using (column("R1_11")):(column("R1_21")):(column("R1_31")) with lines lc rgb "#1f77b4" title "tip of R_1 e_1", \
      ARG3 using (column("R2_11")):(column("R2_21")):(column("R2_31")) with lines lc rgb "#d62728" title "tip of R_2 e_1", \
      ARG3 every every_snapshot using (0):(0):(0):(column("R1_11")):(column("R1_21")):(column("R1_31")) \
           with vectors nohead lc rgb "#1f77b4" lw 0.7 notitle, \
      ARG3 every every_snapshot using (0):(0):(0):(column("R2_11")):(column("R2_21")):(column("R2_31")) \
           with vectors nohead lc rgb "#d62728" lw 0.7 notitle
unset zlabel
set key default
set xtics autofreq
set ytics autofreq

# (b) control moment with knots
set title "(b) control moment u at the joint (inertial frame), with the optimized knots (circles)"
set xlabel "t [s]"
set ylabel "u [N m]"
set key top right
set grid
plot ARG3 using "t":"u1" with lines lc 1 title "u_1", \
     ARG3 using "t":"u2" with lines lc 2 title "u_2", \
     ARG3 using "t":"u3" with lines lc 3 title "u_3", \
     ARG5 using "t":"u1" with points pt 6 ps 1.5 lc 1 notitle, \
     ARG5 using "t":"u2" with points pt 6 ps 1.5 lc 2 notitle, \
     ARG5 using "t":"u3" with points pt 6 ps 1.5 lc 3 notitle

# (c) convergence
set title "(c) convergence of SLSQP"
set xlabel "SLSQP evaluation"
set ylabel "terminal violation"
set logscale y
set format y "10^{%L}"
set y2label "cost [N^2 m^2 s]"
set logscale y2
set format y2 "10^{%L}"
set y2tics
set ytics nomirror
set key at graph 0.98, graph 0.95 right opaque box
plot ARG4 using "evaluation":(positive(column("violation"))) with lines lc rgb "#d62728" title "violation (left axis)", \
     ARG4 using "evaluation":(positive(column("cost"))) axes x1y2 with lines lc rgb "#1f77b4" title "cost (right axis)"
unset logscale y
unset logscale y2
unset y2tics
unset y2label
set ytics mirror
set format y "%g"
set key default

# (d) angular velocities
set title "(d) angular velocities Ω_1, Ω_2 (body frames)"
set xlabel "t [s]"
set ylabel "Ω [rad/s]"
plot ARG3 using "t":"Omega1_1" with lines lc 1 title "Ω_{1,1}", \
     ARG3 using "t":"Omega1_2" with lines lc 2 title "Ω_{1,2}", \
     ARG3 using "t":"Omega1_3" with lines lc 3 title "Ω_{1,3}", \
     ARG3 using "t":"Omega2_1" with lines dt 2 lc 1 title "Ω_{2,1}", \
     ARG3 using "t":"Omega2_2" with lines dt 2 lc 2 title "Ω_{2,2}", \
     ARG3 using "t":"Omega2_3" with lines dt 2 lc 3 title "Ω_{2,3}"

unset multiplot
