## crslab's test of the course's map parsing: true when TEXT is a hexadecimal number, the way the
## course's isHex decides it (hex2dec does not throw; the compat hex2dec throws as MATLAB's does).
function yes = crs_is_hex (text)
  try
    hex2dec (text);
    yes = true;
  catch
    yes = false;
  end
end
