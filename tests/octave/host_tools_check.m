## crslab's Octave check of the host tools against a running `crslab sim --serial-dir`, one
## generation per run (Octave starts slowly: one script does every check). Arguments: the
## generation (A or B), SerialC's path, the folder of crslab's Octave compat files. Run from a
## folder beside the one holding the map, as the course's matlab/ folder is. It prints what it
## read; the Python test (tests/test_host_tools_octave.py) judges it.
args = argv ();
gen = args{1}; port = args{2};
addpath (fileparts (mfilename ("fullpath")));  # the crs_* functions beside this script
addpath (args{3});
crs_octave_compat ();

map = crs_parse_map (crs_map_file (gen));
for i = 1:rows (map)
  printf ('map %s %s %s\n', map{i, :});
end

x = crs_serialread ('whattoprint', 1, port, gen);
printf ('read whattoprint: %.9g %s %dx%d\n', x, class (x), rows (x), columns (x));
printf ('read Kp1: %.9g\n', crs_serialread ('Kp1', 1, port, gen));

## the lab keeps 100 samples after 5 s: ask until it says so (each read waits for its reply)
polls = 0;
do
  samples = crs_serialread ('samples', 1, port, gen);
  polls++;
until samples >= 100 || polls > 100000
printf ('read samples: %.9g\n', samples);

t = crs_serialread ('timearray', 100, port, gen);
printf ('read timearray: %dx%d %s\n', rows (t), columns (t), sprintf ('%.9g ', t));
th = crs_serialread ('theta1array', 100, port, gen);
printf ('read theta1array: %dx%d %s\n', rows (th), columns (th), sprintf ('%.9g ', th));

crs_serialwrite ('Kp1', 40, port, gen);
printf ('after writing Kp1 40: %.9g\n', crs_serialread ('Kp1', 1, port, gen));
crs_serialwrite ('whattoprint', -2.5, port, gen);
printf ('after writing whattoprint -2.5: %.9g\n', crs_serialread ('whattoprint', 1, port, gen));
if gen == 'A'
  printf ('read matlabLock: %.9g\n', crs_serialread ('matlabLock', 1, port, gen));
end
try
  crs_serialread ('nosuchvariable', 1, port, gen);
catch err
  printf ('error: %s: %s\n', err.identifier, err.message);
end
printf ('done\n');
