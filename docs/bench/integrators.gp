# popc bench integrators --plot: work-precision diagram (gnuplot 5)
set terminal pngcairo size 900,640 noenhanced
set output 'integrators.png'
set logscale xy
set format y '1e%L'
set xlabel 'time per control step (ns), closed loop, no log'
set ylabel 'max |x - x_exact| at the samples (m)'
set title 'work-precision, same force sequence for every integrator'
set grid
set key top right
set arrow from 38.3991, graph 0 to 38.3991, graph 1 nohead dt 2 lc rgb 'black'
set label 'exact (the reference, error 0)' at 38.3991, graph 0.05 rotate by 90 offset -1,0
set label 'rounding floor 1.7e-15 m' at graph 0.6, first 1.7053e-15 offset 0,0.6
set arrow from graph 0, first 1.7053e-15 to graph 1, first 1.7053e-15 nohead dt 3 lc rgb 'gray'
set label 'p = 1.99' at 2858.27, 2.12667e-13 offset 1,1 tc ls 1
set label 'p = 4.00' at 176.47, 1.24722e-14 offset 1,-1 tc ls 2
set label 'p = 1.00' at 8754.71, 8.30804e-08 offset 1,1 tc ls 3
set label 'p = 1.00' at 8057.93, 1.19205e-07 offset 1,-1 tc ls 4
plot 'integrators.dat' index 0 using 1:2 with linespoints ls 1 title 'trapezoid', \
     'integrators.dat' index 1 using 1:2 with linespoints ls 2 title 'rk4', \
     'integrators.dat' index 2 using 1:2 with linespoints ls 3 title 'semi-implicit-euler', \
     'integrators.dat' index 3 using 1:2 with linespoints ls 4 title 'euler'
