# Hertz against linear contact at equal peak stiffness: F_m with error bars against f_r, from
# the CSV written by docs/plot/hertz_vs_linear.py.
# Usage: gnuplot -e "csv='out/beyond/hertz-vs-linear.csv'; png='docs/img/beyond-hertz.png'" docs/plot/hertz-vs-linear.gp
set terminal pngcairo size 900,550 font 'sans,11'
set output png
set datafile separator ','
set datafile columnheaders
set grid
set key top right
set xlabel 'f_r'
set ylabel 'F_m (reduced)'
set title 'Table 4 row (Nm=46, fc=559, eps=0.1, e_r=0.22), harmonic, 1000 periods: equal peak tangent stiffness' noenhanced
set xrange [0.4:1.6]
set yrange [0:*]
plot csv using (column('f_r') - 0.01):(column('F_m_linear')):(column('F_m_linear_error')) with yerrorlines pt 7 lw 2 title 'linear, k p', \
     csv using (column('f_r') + 0.01):(column('F_m_hertz')):(column('F_m_hertz_error')) with yerrorlines pt 5 lw 2 title 'Hertz, c k p^{3/2}'
