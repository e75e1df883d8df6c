# Plots obvh_bench accuracy's CSV: speed on the first scene beside the error rates, one bar per mode.
# Usage: gnuplot -e "csv='out/accuracy.csv'; png='out/accuracy.png'" tools/bench/accuracy_plot.gp
set datafile separator ","
set terminal pngcairo size 1500,520 font ",10" noenhanced
set output png
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.85 border -1
set boxwidth 0.9
set key top left
set offsets 0, 0, graph 0.15, 0
set grid ytics
set xtics rotate by -25
set yrange [0:*]
set multiplot layout 1,3 title "What accuracy costs: speed on the first scene vs errors of the accuracy study"

set title "speed (Mrays/s, higher is better)"
plot csv using 9:xtic(1) title columnhead(9), '' using 10 title columnhead(10)

set title "closed meshes: leaks and double reports per million rays"
plot csv using 3:xtic(1) title columnhead(3), '' using 4 title columnhead(4)

set title "grazing rays at skinny triangles: wrong answers"
plot csv using 7:xtic(1) title columnhead(7), '' using 8 title columnhead(8)
unset multiplot
