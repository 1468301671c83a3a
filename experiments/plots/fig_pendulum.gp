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
# Size, fonts and keys: ocp_figure.gp.

if (ARGC != 4) {
    print "usage: gnuplot -c fig_pendulum.gp OUT.png TITLE trajectory.csv history.csv"
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
load plots_dir."ocp_figure.gp"

# (a) maneuver: a picture of the motion in the unit box (no tick labels).
set title "(a) maneuver (e_3 up)" offset 0, 2.0
unset xlabel
unset ylabel
set view 62, 30, 1.35, 1
set xyplane at 0
set border 15
unset xtics
unset ytics
unset ztics
unset grid
set xrange [-1:1]
set yrange [-1:1]
set zrange [-1:1]
set label 101 "R e_1" at screen 0.03, screen 0.75 left textcolor rgb c1 font @font_6
set label 102 "R e_3" at screen 0.03, screen 0.725 left textcolor rgb c2 font @font_6
splot ARG3 using (column("R11")):(column("R21")):(column("R31")) with lines lc rgb c1, \
      ARG3 using (column("R13")):(column("R23")):(column("R33")) with lines lc rgb c2, \
      ARG3 every every_snapshot using (0):(0):(0):(column("R11")):(column("R21")):(column("R31")) \
           with vectors nohead lc rgb c1 lw 0.5, \
      ARG3 every every_snapshot using (0):(0):(0):(column("R13")):(column("R23")):(column("R33")) \
           with vectors nohead lc rgb c2 lw 0.5
unset label
set border 31
set autoscale
set xtics; set ytics
set grid
set xlabel offset 0, 0.6
set ylabel offset 0.8, 0
set title offset 0, 1.3
@time_tics

# (b) control moment
set title "(b) control moment"
tic_file = ARG3; tic_columns = "u1 u2 u3"; @value_tics
set xlabel "t [s]"
set ylabel "u [N m]"
set label 101 "u_1" at graph 0.2, graph 1 offset 0, row_1 center textcolor rgb c1 font @font_6
set label 102 "u_2" at graph 0.5, graph 1 offset 0, row_1 center textcolor rgb c2 font @font_6
set label 103 "u_3" at graph 0.8, graph 1 offset 0, row_1 center textcolor rgb c3 font @font_6
plot ARG3 using "t":"u1" with lines lc rgb c1, \
     ARG3 using "t":"u2" with lines lc rgb c2, \
     ARG3 using "t":"u3" with lines lc rgb c3
unset label

# (c) convergence; the condition numbers κ on the right axis
set title "(c) convergence (κ: right)"
stats ARG4 using "iteration" nooutput
set xtics 0, iteration_step(STATS_max); set mxtics default; set format x "%g"
set xlabel "outer iteration"
set ylabel "violation"
set logscale y
set format y "10^{%L}"
set ytics 1e4 nomirror
set logscale y2
set format y2 "10^{%L}"
set y2tics 1e10 font @font_6 offset -0.5, 0
set label 101 "violation" at graph 0.5, graph 1 offset 0, row_2 center textcolor rgb c2 font @font_6
set label 102 "κ block" at graph 0.25, graph 1 offset 0, row_1 center textcolor rgb c3 font @font_6
set label 103 "κ full" at graph 0.75, graph 1 offset 0, row_1 center textcolor rgb c4 font @font_6
plot ARG4 using "iteration":(positive(column("violation"))) with linespoints pt 6 ps 0.4 lc rgb c2, \
     ARG4 using "iteration":(positive(column("cond_inverted"))) axes x1y2 with linespoints pt 2 ps 0.4 lc rgb c3, \
     ARG4 using "iteration":(positive(column("cond_sensitivity"))) axes x1y2 with linespoints pt 4 ps 0.4 lc rgb c4
unset label
unset logscale y
unset logscale y2
unset y2tics
set ytics autofreq mirror
set format y "%g"

# (d) angular velocity
set title "(d) angular velocity"
tic_file = ARG3; tic_columns = "Omega1 Omega2 Omega3"; @value_tics
@time_tics
set xlabel "t [s]"
set ylabel "Ω [rad/s]"
set label 101 "Ω_1" at graph 0.2, graph 1 offset 0, row_1 center textcolor rgb c1 font @font_6
set label 102 "Ω_2" at graph 0.5, graph 1 offset 0, row_1 center textcolor rgb c2 font @font_6
set label 103 "Ω_3" at graph 0.8, graph 1 offset 0, row_1 center textcolor rgb c3 font @font_6
plot ARG3 using "t":"Omega1" with lines lc rgb c1, \
     ARG3 using "t":"Omega2" with lines lc rgb c2, \
     ARG3 using "t":"Omega3" with lines lc rgb c3
unset label

unset multiplot
