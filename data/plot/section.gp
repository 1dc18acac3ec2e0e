# gapchain-poincare's figure. Regenerate: gnuplot section.gp (in the output folder).
set terminal pngcairo size 900,800 font 'sans,11'
set output 'section.png'
set datafile separator ','
set grid
set key off
set xlabel '@X@'
set ylabel '@Y@'
set title '@TITLE@ (@COUNT@ points)'
plot 'section.csv' every ::1 using @XCOLUMN@:@YCOLUMN@ with points pt 7 ps 0.4 lc rgb '#1f4e9c'
