## crslab's test client, written in the course's style (the calls ME446_serialread makes): find the
## map beside the scripts, parse it, take the last variable whose name contains NAME, send the read
## request as a hex string through sscanf, skip to the reply's '*' and read VARSIZE floats.
## GEN is 'A' (serial, as the Gen A scripts) or 'B' (serialport); PORT replaces 'COM1'.
function out3 = crs_serialread (name, varsize, port, gen)
  s = instrfind;
  if length (s) > 0
    fclose (s);
  end
  map = crs_parse_map (crs_map_file (gen));
  address = '';
  for i = 1:rows (map)
    if ! isempty (strfind (map{i, 1}, name))
      address = map{i, 2};
    end
  end
  if isempty (address)
    throw (MException ('MATLAB:VarNotFound', 'Variable name not found.'));
  end
  hex = strcat ('2A0932', address, dec2hex (varsize, 4));
  if gen == 'A'
    s = serial (port);
    set (s, 'BaudRate', 115200);
  else
    s = serialport (port, 115200);
  end
  s.InputBufferSize = 15000;
  fopen (s);
  fwrite (s, sscanf (hex, '%2X'));
  for i = 1:101
    b = fread (s, 1);
    if b == 42
      fread (s, 1);
      code = fread (s, 1);
      if code == 51
        out3 = fread (s, varsize, 'float32');
        break;
      end
    end
  end
  fclose (s);
  delete (s);
  clear s
end
