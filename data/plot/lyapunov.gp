# gapchain-lyapunov's figure. Regenerate: run gnuplot on this script in the output's folder.
set terminal pngcairo size 1000,650 font 'sans,11'
set output '@PNG@'
set datafile separator ','
set grid
set xlabel 'reduced time'
set ylabel 'running exponent estimate'
set key outside right
set title 'Lyapunov exponents: convergence'
plot for [c=2:@LAST@] '@CSV@' using 1:c with lines lw 1.5 title columnheader(c)
