# Fig 13's line: the period-1 family and the doubled (period 2, 4) branches over the
# brute-force diagram. Regenerate (the commands of docs/orbits.md first):
#   gnuplot -e "bif='/tmp/bif13/summary.csv'; dirs='/tmp/cont13 /tmp/p2a /tmp/p2b'; out='docs/img/orbits-doubled.png'" docs/plot/orbits_doubled.gp
# dirs: gapchain-continue output folders (branch.csv, special.csv), separated by spaces.
set terminal pngcairo size 1200,700 font 'sans,11'
set output out
set datafile separator ','
set grid
set key outside right
set xlabel 'f_r'
set ylabel 'F_m (reduced)'
set title 'Fig 13 line (Nm=5, fc=60, eps=0.5, e_r=0.06): period 1 (circles), 2 (triangles), 4 (squares); stable blue, unstable red'
set xrange [2.15:4.5]
branch(dir) = dir.'/branch.csv'
special(dir) = dir.'/special.csv'
# column 2 is the period, 6 stability (branch.csv: value,period,F_m,F_m_error,u1,stable,...)
pt_of(k) = k == 1 ? 7 : (k == 2 ? 9 : 5)
plot bif every ::1 using 1:3 with points pt 7 ps 0.2 lc rgb '#bbbbbb' title 'brute force', \
     for [d in dirs] branch(d) every ::1 using 1:($6 == 1 ? $3 : 1/0):(pt_of($2)) with points pt variable ps 0.5 lc rgb '#1f4e9c' notitle, \
     for [d in dirs] branch(d) every ::1 using 1:($6 == 0 ? $3 : 1/0):(pt_of($2)) with points pt variable ps 0.3 lc rgb '#d62728' notitle, \
     for [d in dirs] special(d) every ::1 using 2:(strcol(1) eq 'period_doubling' ? $4 : 1/0) with points pt 4 ps 1.6 lc rgb '#2ca02c' notitle, \
     for [d in dirs] special(d) every ::1 using 2:(strcol(1) eq 'fold' ? $4 : 1/0) with points pt 8 ps 1.6 lc rgb 'black' notitle, \
     NaN with points pt 4 ps 1.6 lc rgb '#2ca02c' title 'period doubling', \
     NaN with points pt 8 ps 1.6 lc rgb 'black' title 'fold'
