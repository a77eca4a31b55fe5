## crslab: MATLAB's serial (PORT, NAME, VALUE, ...) for the course's Gen A scripts (see crs_octave_compat).
function s = serial (port, varargin)
  s = crs_serial_compat (port, 9600, varargin{:});
endfunction
