# Heat map of the maximal force per contact against a swept parameter (Figs 8, 9, 15), from
# the output of docs/plot/per_contact.py.
# Usage: gnuplot -e "dat='fig15.dat'; png='out.png'; xlabel='f_r'; title='...'" docs/plot/per-contact-map.gp
set terminal pngcairo size 1000,600 font 'sans,11'
set output png
set datafile separator ','
set xlabel xlabel noenhanced
set ylabel 'contact (0 = left wall, Nm = right wall)'
set cblabel 'max reduced force'
set title title noenhanced
set view map
set autoscale xfix
set autoscale yfix
set palette rgbformulae 33,13,10
plot dat using 1:2:3 with image notitle
