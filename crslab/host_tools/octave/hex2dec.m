## crslab: hex2dec as MATLAB's, which throws on text that is not hexadecimal (Octave's returns NaN,
## and the course's isHex, hence parseMap, depends on the error). See crs_octave_compat.
function d = hex2dec (s)
  s = char (s);
  if (isempty (s) || any (! isxdigit (s(:)) & ! isspace (s(:))))
    error ("MATLAB:hex2dec:IllegalHexadecimal", ...
           "Input to hex2dec should have just 0-9, a-f, or A-F.");
  endif
  d = base2dec (s, 16);
endfunction
