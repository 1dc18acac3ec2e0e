# gapchain-spectrum's figure. Regenerate: gnuplot spectrum.gp (in the output folder).
set terminal pngcairo size 1000,600 font 'sans,11'
set output 'spectrum.png'
set datafile separator ','
set logscale y
set grid
set key off
set xlabel 'f / f_r'
set ylabel 'PSD of @VARIABLE@'
set title 'Welch PSD (@SEGMENTS@ segments of @SEGMENT@)'
plot 'psd.csv' every ::1 using 2:3 with lines lw 1.2 lc rgb '#1f4e9c'
