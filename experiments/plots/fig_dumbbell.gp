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
# the attitude readable). Size, fonts and curve names: ocp_figure.gp.

if (ARGC != 4) {
    print "usage: gnuplot -c fig_dumbbell.gp OUT.png TITLE trajectory.csv history.csv"
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

# (a) maneuver
set title "(a) maneuver (orbit plane)"
set xlabel "x_1"
set ylabel "x_2"
set size ratio -1
set xtics 0.5
set ytics 0.5
rod = 0.1
set label 101 "x" at graph 0.3, graph 1 offset 0, row_1 center textcolor rgb c1 font @font_6
set label 102 "R e_1" at graph 0.7, graph 1 offset 0, row_1 center textcolor rgb c2 font @font_6
plot ARG3 using "x1":"x2" with lines lc rgb c1, \
     ARG3 every every_snapshot using (column("x1") - rod/2*column("R11")):(column("x2") - rod/2*column("R21")):(rod*column("R11")):(rod*column("R21")) \
          with vectors nohead lc rgb c2 lw 1.5
unset label
set size noratio
set ytics autofreq
@time_tics

# (b) control moment (solid, body frame) and force (dashed, inertial frame)
set title "(b) u^m solid, u^f dashed"
tic_file = ARG3; tic_columns = "um1 um2 um3 uf1 uf2 uf3"; @value_tics
set xlabel "t"
set ylabel "u"
set label 101 "u_1" at graph 0.2, graph 1 offset 0, row_1 center textcolor rgb c1 font @font_6
set label 102 "u_2" at graph 0.5, graph 1 offset 0, row_1 center textcolor rgb c2 font @font_6
set label 103 "u_3" at graph 0.8, graph 1 offset 0, row_1 center textcolor rgb c3 font @font_6
plot ARG3 using "t":"um1" with lines lc rgb c1, \
     ARG3 using "t":"um2" with lines lc rgb c2, \
     ARG3 using "t":"um3" with lines lc rgb c3, \
     ARG3 using "t":"uf1" with lines dt 2 lc rgb c1, \
     ARG3 using "t":"uf2" with lines dt 2 lc rgb c2, \
     ARG3 using "t":"uf3" with lines dt 2 lc rgb c3
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
set y2tics 10 font @font_6 offset -0.5, 0
set label 101 "violation" at graph 0.5, graph 1 offset 0, row_2 center textcolor rgb c2 font @font_6
set label 102 "κ inv" at graph 0.25, graph 1 offset 0, row_1 center textcolor rgb c3 font @font_6
set label 103 "κ full" at graph 0.75, graph 1 offset 0, row_1 center textcolor rgb c4 font @font_6
plot ARG4 using "iteration":(positive(column("violation"))) with lines lc rgb c2, \
     ARG4 using "iteration":(positive(column("cond_inverted"))) axes x1y2 with lines lc rgb c3, \
     ARG4 using "iteration":(positive(column("cond_sensitivity"))) axes x1y2 with lines dt 2 lc rgb c4
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
set xlabel "t"
set ylabel "Ω"
set label 101 "Ω_1" at graph 0.2, graph 1 offset 0, row_1 center textcolor rgb c1 font @font_6
set label 102 "Ω_2" at graph 0.5, graph 1 offset 0, row_1 center textcolor rgb c2 font @font_6
set label 103 "Ω_3" at graph 0.8, graph 1 offset 0, row_1 center textcolor rgb c3 font @font_6
plot ARG3 using "t":"Omega1" with lines lc rgb c1, \
     ARG3 using "t":"Omega2" with lines lc rgb c2, \
     ARG3 using "t":"Omega3" with lines lc rgb c3
unset label

unset multiplot
