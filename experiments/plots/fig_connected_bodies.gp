# fig_connected_bodies.gp: the paper's Fig. 5 for the direct two-connected-bodies example: (a) the
# maneuver, (b) the control moment with its knots, (c) the convergence of SLSQP, (d) the angular
# velocities.
#
# Usage:
#   gnuplot -c fig_connected_bodies.gp OUT.png TITLE trajectory.csv history.csv knots.csv [BEST STARTS]
#
# The files are ocp-connected-bodies-{trajectory,history,knots}.csv written by
# `lgvi-testbed ocp connected-bodies`; columns are read by name. (a) draws the paths of the tips
# of the body-fixed unit vectors R1 e1 (body 1) and R2 e1 (body 2) in the inertial frame, with
# the vectors at eleven equally spaced times: the maneuver turns both bodies by 180 deg about e1
# and leaves their relative attitude unchanged. BEST and STARTS (the summary's best_start and
# starts): panel (c) draws that start's convergence alone (slsqp_panel.gp). Size, fonts and
# curve names: ocp_figure.gp.

if (ARGC != 5 && ARGC != 7) {
    print "usage: gnuplot -c fig_connected_bodies.gp OUT.png TITLE trajectory.csv history.csv knots.csv [BEST STARTS]"
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

# (a) maneuver: a picture of the motion in the unit box (no tick labels)
set title "(a) maneuver" offset 0, 2.0
unset xlabel
unset ylabel
set view 62, 30, 1.35, 1
set xyplane at -1.1
set border 15
unset xtics
unset ytics
unset ztics
unset grid
set xrange [-1:1]
set yrange [-1:1]
set zrange [-1:1]
set label 101 "R_1 e_1" at screen 0.03, screen 0.72 left textcolor rgb c1 font @font_6
set label 102 "R_2 e_1" at screen 0.03, screen 0.695 left textcolor rgb c2 font @font_6
splot ARG3 using (column("R1_11")):(column("R1_21")):(column("R1_31")) with lines lc rgb c1, \
      ARG3 using (column("R2_11")):(column("R2_21")):(column("R2_31")) with lines lc rgb c2, \
      ARG3 every every_snapshot using (0):(0):(0):(column("R1_11")):(column("R1_21")):(column("R1_31")) \
           with vectors nohead lc rgb c1 lw 0.5, \
      ARG3 every every_snapshot using (0):(0):(0):(column("R2_11")):(column("R2_21")):(column("R2_31")) \
           with vectors nohead lc rgb c2 lw 0.5
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

# (b) control moment at the joint (inertial frame) with the optimized knots (circles)
set title "(b) joint moment (o: knots)"
tic_file = ARG3; tic_columns = "u1 u2 u3"; @value_tics
set xlabel "t [s]"
set ylabel "u [N m]"
set label 101 "u_1" at graph 0.2, graph 1 offset 0, row_1 center textcolor rgb c1 font @font_6
set label 102 "u_2" at graph 0.5, graph 1 offset 0, row_1 center textcolor rgb c2 font @font_6
set label 103 "u_3" at graph 0.8, graph 1 offset 0, row_1 center textcolor rgb c3 font @font_6
plot ARG3 using "t":"u1" with lines lc rgb c1, \
     ARG3 using "t":"u2" with lines lc rgb c2, \
     ARG3 using "t":"u3" with lines lc rgb c3, \
     ARG5 using "t":"u1" with points pt 6 ps 0.6 lc rgb c1, \
     ARG5 using "t":"u2" with points pt 6 ps 0.6 lc rgb c2, \
     ARG5 using "t":"u3" with points pt 6 ps 0.6 lc rgb c3
unset label

# (c) convergence
history = ARG4
cost_unit = "N^2 m^2 s"
load plots_dir."slsqp_panel.gp"

# (d) angular velocities: body 1 solid, body 2 dashed (body frames)
set title "(d) Ω_1 solid, Ω_2 dashed"
tic_file = ARG3; tic_columns = "Omega1_1 Omega1_2 Omega1_3 Omega2_1 Omega2_2 Omega2_3"; @value_tics
@time_tics
set xlabel "t [s]"
set ylabel "Ω [rad/s]"
set label 101 "Ω_{i,1}" at graph 0.2, graph 1 offset 0, row_1 center textcolor rgb c1 font @font_6
set label 102 "Ω_{i,2}" at graph 0.5, graph 1 offset 0, row_1 center textcolor rgb c2 font @font_6
set label 103 "Ω_{i,3}" at graph 0.8, graph 1 offset 0, row_1 center textcolor rgb c3 font @font_6
plot ARG3 using "t":"Omega1_1" with lines lc rgb c1, \
     ARG3 using "t":"Omega1_2" with lines lc rgb c2, \
     ARG3 using "t":"Omega1_3" with lines lc rgb c3, \
     ARG3 using "t":"Omega2_1" with lines dt 2 lc rgb c1, \
     ARG3 using "t":"Omega2_2" with lines dt 2 lc rgb c2, \
     ARG3 using "t":"Omega2_3" with lines dt 2 lc rgb c3
unset label

unset multiplot
