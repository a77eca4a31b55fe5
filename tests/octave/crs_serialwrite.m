## crslab's test client, written in the course's style (the calls ME446_serialwrite makes): the
## write request's header and address as a hex string, then the value as a float32, in two fwrites.
function crs_serialwrite (name, value, port, gen)
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
  if gen == 'A'
    s = serial (port);
    set (s, 'BaudRate', 115200);
  else
    s = serialport (port, 115200);
  end
  s.InputBufferSize = 5000;
  fopen (s);
  fwrite (s, sscanf (strcat ('2A0B33', address), '%2X'));
  fwrite (s, value, 'float32');
  fclose (s);
  delete (s);
  clear s
end
