# fig_cart_pendulum.gp: the paper's Fig. 4 for the direct 3D-pendulum-on-a-cart example: (a) the
# maneuver, (b) the control force with its knots, (c) the convergence of SLSQP, (d) the
# angular velocity and the cart velocity.
#
# Usage:
#   gnuplot -c fig_cart_pendulum.gp OUT.png TITLE trajectory.csv history.csv knots.csv [BEST STARTS]
#
# The files are ocp-cart-pendulum-{trajectory,history,knots}.csv written by
# `lgvi-testbed ocp cart-pendulum`; columns are read by name. In (a) the vertical axis points up,
# i.e. along -e3 (gravity acts along +e3): the cart's path (x, y) lies in the plane 0 and the
# pendulum is drawn from the cart to the tip of R e3 (its mass centre, d = e3 m in the paper's
# parameters) at eleven equally spaced times. BEST and STARTS (the summary's best_start and
# starts): panel (c) draws that start's convergence alone (slsqp_panel.gp). Size, fonts and
# curve names: ocp_figure.gp.

if (ARGC != 5 && ARGC != 7) {
    print "usage: gnuplot -c fig_cart_pendulum.gp OUT.png TITLE trajectory.csv history.csv knots.csv [BEST STARTS]"
    exit status 2
}

# The shared files (terminal.gp ...) are loaded from this script's directory.
plots_dir = ARG0
while (strlen(plots_dir) > 0 && plots_dir[strlen(plots_dir):] ne "/") { plots_dir = plots_dir[:strlen(plots_dir)-1] }
fig_out = ARG1
fig_title = ARG2
stats ARG3 using 1 nooutput
every_snapshot = int((STATS_records - 1) / 10)
t_final = STATS_max
best_start = (ARGC == 7 ? int(ARG6) : -1)
starts = (ARGC == 7 ? int(ARG7) : 0)
load plots_dir."ocp_figure.gp"

# (a) maneuver: the cart's path in the plane 0, the pendulum (grey) at eleven times; a picture
# of the motion (no tick labels), x and y to one scale
set title "(a) maneuver (up: -e_3)" offset 0, 2.6
unset xlabel
unset ylabel
set view 62, 30, 1.3, 1
set view equal xy
set xyplane at -1.1
set border 15
unset xtics
unset ytics
unset ztics
unset grid
set label 101 "cart" at screen 0.03, screen 0.72 left textcolor rgb c1 font @font_6
set label 102 "mass centre" at screen 0.03, screen 0.695 left textcolor rgb c2 font @font_6
splot ARG3 using "x":"y":(0) with lines lc rgb c1, \
      ARG3 using (column("x") + column("R13")):(column("y") + column("R23")):(-column("R33")) with lines lc rgb c2, \
      ARG3 every every_snapshot using "x":"y":(0):(column("R13")):(column("R23")):(-column("R33")) \
           with vectors nohead lc rgb c4 lw 0.5
unset label
set autoscale
set border 31
set xtics autofreq offset 0, 0.3
set ytics autofreq offset 0.4, 0
set grid
set xlabel offset 0, 0.6
set ylabel offset 0.8, 0
set title offset 0, 1.3
@time_tics

# (b) control force with the optimized knots (circles)
set title "(b) cart force (o: knots)"
tic_file = ARG3; tic_columns = "u1 u2"; @value_tics
set xlabel "t [s]"
set ylabel "u [N]"
set label 101 "u_x" at graph 0.3, graph 1 offset 0, row_1 center textcolor rgb c1 font @font_6
set label 102 "u_y" at graph 0.7, graph 1 offset 0, row_1 center textcolor rgb c2 font @font_6
plot ARG3 using "t":"u1" with lines lc rgb c1, \
     ARG3 using "t":"u2" with lines lc rgb c2, \
     ARG5 using "t":"u1" with points pt 6 ps 0.6 lc rgb c1, \
     ARG5 using "t":"u2" with points pt 6 ps 0.6 lc rgb c2
unset label

# (c) convergence
history = ARG4
cost_unit = "N^2 s"
load plots_dir."slsqp_panel.gp"

# (d) velocities: the pendulum's angular velocity (body frame, solid), the cart's (dashed)
set title "(d) velocities"
tic_file = ARG3; tic_columns = "Omega1 Omega2 Omega3 xdot ydot"; @value_tics
@time_tics
set xlabel "t [s]"
set ylabel "Ω [rad/s], v [m/s]"
set label 101 "Ω_1" at graph 0.2, graph 1 offset 0, row_2 center textcolor rgb c1 font @font_6
set label 102 "Ω_2" at graph 0.5, graph 1 offset 0, row_2 center textcolor rgb c2 font @font_6
set label 103 "Ω_3" at graph 0.8, graph 1 offset 0, row_2 center textcolor rgb c3 font @font_6
set label 104 "dx/dt" at graph 0.3, graph 1 offset 0, row_1 center textcolor rgb c4 font @font_6
set label 105 "dy/dt" at graph 0.7, graph 1 offset 0, row_1 center textcolor rgb "#CC79A7" font @font_6
plot ARG3 using "t":"Omega1" with lines lc rgb c1, \
     ARG3 using "t":"Omega2" with lines lc rgb c2, \
     ARG3 using "t":"Omega3" with lines lc rgb c3, \
     ARG3 using "t":"xdot" with lines dt 2 lc rgb c4, \
     ARG3 using "t":"ydot" with lines dt 2 lc rgb "#CC79A7"
unset label

unset multiplot
