# fig_cart_pendulum.gp: the paper's Fig. 4 for the direct 3D-pendulum-on-a-cart example: (a) the
# maneuver, (b) the control force with its knots, (c) the convergence of SLSQP, (d) the
# angular velocity and the cart velocity.
#
# Usage:
#   gnuplot -c fig_cart_pendulum.gp OUT.png TITLE trajectory.csv history.csv knots.csv
#
# The files are ocp-cart-pendulum-{trajectory,history,knots}.csv written by
# `lgvi-testbed ocp cart-pendulum`; columns are read by name. In (a) the vertical axis points up,
# i.e. along -e3 (gravity acts along +e3): the cart's path (x, y) lies in the plane 0 and the
# pendulum is drawn from the cart to the tip of R e3 (its mass centre, d = e3 m in the paper's
# parameters) at eleven equally spaced times.

if (ARGC != 5) {
    print "usage: gnuplot -c fig_cart_pendulum.gp OUT.png TITLE trajectory.csv history.csv knots.csv"
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
set title "(a) maneuver: cart path and pendulum (vertical axis up = -e_3)"
set xlabel "x [m]"
set ylabel "y [m]"
set zlabel "-e_3 [m]"
set view 62, 30, 1.25, 1
set xyplane at -1.1
set key at screen 0.03, screen 0.92 left
splot ARG3 using "x":"y":(0) with lines lc rgb "#1f77b4" title "cart", \
      ARG3 using (column("x") + column("R13")):(column("y") + column("R23")):(-column("R33")) with lines lc rgb "#d62728" title "pendulum mass centre", \
      ARG3 every every_snapshot using "x":"y":(0):(column("R13")):(column("R23")):(-column("R33")) \
           with vectors nohead lc rgb "#7f7f7f" lw 1 notitle
unset zlabel
set key default

# (b) control force with knots
set title "(b) control force u on the cart, with the optimized knots (circles)"
set xlabel "t [s]"
set ylabel "u [N]"
set key top right
set grid
plot ARG3 using "t":"u1" with lines lc 1 title "u_x", \
     ARG3 using "t":"u2" with lines lc 2 title "u_y", \
     ARG5 using "t":"u1" with points pt 6 ps 1.5 lc 1 notitle, \
     ARG5 using "t":"u2" with points pt 6 ps 1.5 lc 2 notitle

# (c) convergence
set title "(c) convergence of SLSQP"
set xlabel "SLSQP evaluation"
set ylabel "terminal violation"
set logscale y
set format y "10^{%L}"
set y2label "cost [N^2 s]"
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

# (d) velocities
set title "(d) pendulum angular velocity Ω (body frame) and cart velocity"
set xlabel "t [s]"
set ylabel "Ω [rad/s],  dq/dt [m/s]"
plot ARG3 using "t":"Omega1" with lines lc 1 title "Ω_1", \
     ARG3 using "t":"Omega2" with lines lc 2 title "Ω_2", \
     ARG3 using "t":"Omega3" with lines lc 3 title "Ω_3", \
     ARG3 using "t":"xdot" with lines dt 2 lc 4 title "dx/dt", \
     ARG3 using "t":"ydot" with lines dt 2 lc 6 title "dy/dt"

unset multiplot
