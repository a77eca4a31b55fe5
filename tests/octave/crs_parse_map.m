## crslab's own implementation of what the course's parseMap does with a TI linker map (written
## from docs/host-tools.md's description, not copied): pass 1 takes the third and fourth words of
## the first line naming .my_arrs and of the first naming .my_vars (origin and length), up to the
## line "SORTED BY Symbol Address"; pass 2 keeps each later line whose second word is hex and third
## is not, inside either section, as {name without its first character, address text, type}.
function map = crs_parse_map (path)
  fid = fopen (path, 'r');
  if fid < 0
    error ('crslab:map', 'cannot open %s', path);
  end
  arrs = []; vars = [];
  line = fgetl (fid);
  while ischar (line)
    if ! isempty (strfind (line, 'SORTED BY Symbol Address'))
      break;
    end
    words = strsplit (strtrim (line));
    if isempty (arrs) && ! isempty (strfind (line, '.my_arrs'))
      arrs = [hex2dec(words{3}), hex2dec(words{4})];
    end
    if isempty (vars) && ! isempty (strfind (line, '.my_vars'))
      vars = [hex2dec(words{3}), hex2dec(words{4})];
    end
    line = fgetl (fid);
  end
  map = cell (0, 3);
  line = fgetl (fid);
  while ischar (line)
    words = strsplit (strtrim (line));
    if numel (words) >= 3 && crs_is_hex (words{2}) && ! crs_is_hex (words{3})
      address = hex2dec (words{2});
      type = '';
      if address >= arrs(1) && address < arrs(1) + arrs(2)
        type = 'Array Variable';
      elseif address >= vars(1) && address < vars(1) + vars(2)
        type = 'Float Variable';
      end
      if ! isempty (type)
        row = {words{3}(2:end), words{2}, type};
        if rows (map) > 0 && strcmp (map{end, 2}, words{2})
          map(end, :) = row;
        else
          map(end + 1, :) = row;
        end
      end
    end
    line = fgetl (fid);
  end
  fclose (fid);
end
