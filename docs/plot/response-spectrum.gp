# Response spectrum of a row to one record: F_m (newtons and reduced) against the bodies'
# natural frequency f0 = sqrt(K/M) / (2 pi), from a gapchain-sweep CSV over model.K.
# Usage: gnuplot -e "csv='response-spectrum.csv'; M=159.0909; png='out.png'; title='...'" docs/plot/response-spectrum.gp
set terminal pngcairo size 1000,800 font 'sans,11'
set output png
set datafile separator ','
set datafile columnheaders
set multiplot layout 2,1 title title noenhanced
set grid
set logscale x
set xrange [0.4:25]
set key top left noenhanced
f0(K) = sqrt(K / M) / (2 * pi)
set ylabel 'F_m [kN]'
plot csv using (f0(column('axis:model.K'))):(column('F_m_newton') / 1000):(column('F_m_error') * column('F_m_newton') / column('F_m') / 1000) \
     with yerrorlines pt 7 ps 0.6 lw 1.5 title 'max impact force (error bars: F_m_error)'
set xlabel 'natural frequency of one body f0 [Hz]'
set ylabel 'F_m (reduced)'
plot csv using (f0(column('axis:model.K'))):(column('F_m')) with linespoints pt 7 ps 0.6 lw 1.5 lc 2 title 'reduced F_m', \
     csv using (f0(column('axis:model.K'))):(column('e_r')) with lines dt 2 lc 3 title 'e_r = 4 pi^2 f0^2 e / PGA'
unset multiplot
