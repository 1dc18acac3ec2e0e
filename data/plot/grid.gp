# gapchain-modes --grid's figure. Regenerate: gnuplot grid.gp (in the output folder).
set terminal pngcairo size 1000,700 font 'sans,11'
set output 'grid-f1-error.png'
set datafile separator ','
set logscale x
set xrange [@FC_FROM@:@FC_TO@]
set xlabel 'fc'
set ylabel 'Nm'
set cblabel 'relative error of f_{1a}, eq (26)  [%]'
set palette defined (-1.5 'blue', 0 'white', 1.5 'red')
set cbrange [-1.5:1.5]
set yrange [0.5:@NM_MAX@.5]
set key off
set title 'eq (26) against the exact first frequency of the linear chain'
plot 'grid.csv' every ::1 using 2:1:(100*$3) with points pt 5 ps 2.2 palette
