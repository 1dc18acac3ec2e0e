# gapchain-accuracy's figure. Regenerate: gnuplot work_precision.gp (in the output folder).
set terminal pngcairo size 1000,700 font 'sans,11'
set output 'work_precision.png'
set datafile separator ','
set logscale xy
set grid
set key outside right noenhanced
set format x '10^{%L}'
set xlabel 'relative error of F_m'
set ylabel 'wall time [s] (median)'
set title '@TITLE@'
atleast(x) = x < 1e-16 ? 1e-16 : x
plot for [s in 'central_difference rk4 rkf45 rk8pd exact central_difference-nosplit rk4-nosplit'] 'work_precision.csv' every ::1 using (strcol(1) eq s ? atleast($5) : 1/0):8 with linespoints pt 7 ps 0.8 lw 1.5 title s
