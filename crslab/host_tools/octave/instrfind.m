## crslab: MATLAB's instrfind, which the course's scripts call to close stale ports first; Octave
## keeps no list of open ports, so there are none to close (see crs_octave_compat).
function s = instrfind (varargin)
  s = [];
endfunction
