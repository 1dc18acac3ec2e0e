# F_m against f_r1 = f_r / f_1a (eq 31, f_1a of eq 26), one curve per value of a column, from a
# gapchain-sweep CSV (Figs 16 and 17).
# Usage: gnuplot -e "csv='r.csv'; png='out.png'; groupcol='fc'; values='1 10 100 1000'; title='...'" docs/plot/fm-vs-fr1.gp
set terminal pngcairo size 1000,650 font 'sans,11'
set output png
set datafile separator ','
set datafile columnheaders
set grid
set key outside right title groupcol noenhanced
set xlabel 'f_{r1} = f_r / f_{1a}'
set ylabel 'F_m (reduced)'
set title title noenhanced
set xrange [0:3]
f1a(Nm, fc) = sqrt(1 + fc * (1.0 / Nm)**2 * (4.935 - 2.935 * (1.0 / Nm)**1.81))
plot for [v in values] csv using (abs(column(groupcol) - v) < 1e-9 * (1 + v) ? column('f_r') / f1a(column('Nm'), column('fc')) : 1/0):(column('F_m')) \
     smooth unique with linespoints pt 7 ps 0.5 lw 1.5 title v
