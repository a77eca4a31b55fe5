## crs_octave_compat ()
##
## crslab: let GNU Octave (with the instrument-control package) run the course's MATLAB serial
## scripts (ME446_serialread, ME446_serialwrite, ME446_serial_ListVars, parseMap) unchanged but
## for the port name. Call it once per session, after addpath of this folder:
##
##   addpath ('/path/printed/by/crslab serial octave'); crs_octave_compat ();
##
## It loads instrument-control, keeps a handle to its serialport, and puts this folder's stand-ins
## first: serial and serialport (objects with MATLAB's InputBufferSize, Timeout, fopen, fread,
## fclose and delete), instrfind, a hex2dec that rejects non-hex text as MATLAB's does (parseMap's
## isHex depends on it), and MException / throw.

function crs_octave_compat ()
  pkg load instrument-control
  global CRS_SERIALPORT
  CRS_SERIALPORT = @serialport;   # the package's own, before this folder shadows the name
  ## autoloaded functions win over the path: drop the package's, so ours are found
  loaded = autoload ();
  for name = {"serial", "serialport"}
    k = find (strcmp ({loaded.function}, name{1}));
    for i = k(:)'
      autoload (name{1}, loaded(i).file, "remove");
    endfor
  endfor
  warning ("off", "Octave:shadowed-function");
  addpath (fileparts (mfilename ("fullpath")));
endfunction
