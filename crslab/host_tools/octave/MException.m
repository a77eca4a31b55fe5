## crslab: a stand-in for MATLAB's MException (identifier and message), which the course's scripts
## throw when a variable is not in the map. See crs_octave_compat.
function e = MException (identifier, template, varargin)
  e = struct ("identifier", identifier, "message", sprintf (template, varargin{:}));
endfunction
