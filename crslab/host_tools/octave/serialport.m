## crslab: MATLAB's serialport (PORT, BAUD, NAME, VALUE, ...) for the course's Gen B scripts (see
## crs_octave_compat).
function s = serialport (port, baud, varargin)
  if (nargin < 2)
    baud = 9600;
  endif
  s = crs_serial_compat (port, baud, varargin{:});
endfunction
