# fig_pendulum.gp: the paper's Fig. 3 for the indirect 3D-pendulum example: (a) the maneuver,
# (b) the control moment, (c) the convergence of the shooting with the condition numbers of the
# decomposed and full sensitivity derivatives, (d) the angular velocity.
#
# Usage:
#   gnuplot -c fig_pendulum.gp OUT.png TITLE trajectory.csv history.csv
#
# trajectory.csv and history.csv are the ocp-pendulum-{trajectory,history}.csv files written by
# `lgvi-testbed ocp pendulum`; columns are read by name. (a) draws the paths of the tips of two
# body-fixed unit vectors in the inertial frame: R e3 (along the pivot-to-mass-center offset rho)
# and R e1, with the body axes at eleven equally spaced times.

if (ARGC != 4) {
    print "usage: gnuplot -c fig_pendulum.gp OUT.png TITLE trajectory.csv history.csv"
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
set title "(a) maneuver: body axes R e_1, R e_3 (gravity along +e_3)"
set xlabel "e_1"
set ylabel "e_2"
set zlabel "e_3"
set view 62, 30, 1.25, 1
set xyplane at 0
set xtics 0.5
set ytics 0.5
set ztics 0.5
set key at screen 0.03, screen 0.92 left
splot ARG3 using (column("R11")):(column("R21")):(column("R31")) with lines lc rgb "#1f77b4" title "tip of R e_1", \
      ARG3 using (column("R13")):(column("R23")):(column("R33")) with lines lc rgb "#d62728" title "tip of R e_3", \
      ARG3 every every_snapshot using (0):(0):(0):(column("R11")):(column("R21")):(column("R31")) \
           with vectors nohead lc rgb "#1f77b4" lw 0.7 notitle, \
      ARG3 every every_snapshot using (0):(0):(0):(column("R13")):(column("R23")):(column("R33")) \
           with vectors nohead lc rgb "#d62728" lw 0.7 notitle
unset zlabel
set key default
set xtics autofreq
set ytics autofreq

# (b) control moment
set title "(b) control moment u (inertial frame)"
set xlabel "t [s]"
set ylabel "u [N m]"
set key top right
set grid
plot ARG3 using "t":"u1" with lines title "u_1", \
     ARG3 using "t":"u2" with lines title "u_2", \
     ARG3 using "t":"u3" with lines title "u_3"

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
     ARG4 using "iteration":(positive(column("cond_inverted"))) axes x1y2 with linespoints pt 2 lc rgb "#2ca02c" title "cond of the inverted (decomposed) block", \
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
set xlabel "t [s]"
set ylabel "Ω [rad/s]"
plot ARG3 using "t":"Omega1" with lines title "Ω_1", \
     ARG3 using "t":"Omega2" with lines title "Ω_2", \
     ARG3 using "t":"Omega3" with lines title "Ω_3"

unset multiplot
